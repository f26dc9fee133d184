// The per-instance record of the terrain draw, one per drawn patch (std430, matches
// terrain::runtime::PatchInstance in TerrainRenderer.cpp). Positions are metres relative
// to the camera, computed in double on the CPU.
struct PatchInstance {
    vec4 northWestAndSize;  // x, y: camera-relative north-west corner; z, w: size east, south
    ivec4 layerLevel;       // x: texture-array layer, y: level
};

layout(std430, binding = TERRAIN_BINDING_PATCH_INSTANCES) readonly buffer PatchInstances {
    PatchInstance u_instances[];
};
