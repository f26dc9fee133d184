// The planar terrain draw's shared definitions: the per-instance record (one per drawn
// patch, std430, matches terrain::runtime::PatchInstance in TerrainRenderer.h) and the one
// function that places a patch sample relative to the camera. The primitives of an instance
// are terrain_primitives.glsl's.
#include "terrain_primitives.glsl"

struct PatchInstance {
    // x, y: the patch's north-west sample minus the anchor sample (u_cameraSampleFraction),
    // in DEM samples (x east, y south); z: DEM samples per patch sample, 2^(finest − level).
    vec4 originAndStep;
    // x: Err(P), metres (Yusov §4); y: skirt depth, metres: the CPU's bound on the Λ of
    // any neighbouring patch (SkirtDepth.h); z, w: the patch's min and max height, metres.
    vec4 errors;
    ivec4 layerLevel;  // x: texture-array layer, y: level, z, w: the patch's x, y at its level
    // x: quads along a coarse cell's side, 0 when the patch is drawn as blocks; y: the
    // cells' Λ, metres (runtime/lod CoarseCells.h; terrain.tesc draws them).
    vec4 coarseCells;
};

layout(std430, binding = TERRAIN_BINDING_PATCH_INSTANCES) readonly buffer PatchInstances {
    PatchInstance u_instances[];
};

uniform vec2 u_cameraSampleFraction;  // camera x, y in DEM samples minus the anchor, [0, 1)
uniform vec2 u_sampleSpacingM;      // metres per DEM sample, east and south
uniform float u_cameraHeightM;
// The DEM's extent in DEM samples minus the anchor: its first (0, 0) and last (width − 1,
// height − 1) sample. A level's last patches overhang it (they are whole patches of
// clamped samples): nothing beyond it is data, and nothing beyond it is drawn.
uniform vec2 u_demFirstSample;
uniform vec2 u_demLastSample;

// DEM sample (minus the anchor) of patch sample `s`: exact integers near the camera.
vec2 terrainDemSample(PatchInstance patch_, vec2 s) {
    precise vec2 demSample = patch_.originAndStep.xy + s * patch_.originAndStep.z;
    return demSample;
}

// Camera-relative metres of patch sample `s` (integers, apron excluded) at height h.
// Every term up to the subtraction of the camera's fraction is an integer, exact in float
// within 2^24 samples of the camera, so a DEM sample gets bit-identical coordinates from
// every patch and level that holds it: vertices shared by neighbours meet exactly, and
// `precise` keeps the compiler from fusing the operations differently at different uses.
vec3 terrainPositionM(PatchInstance patch_, vec2 s, float heightM) {
    precise vec2 demSample = patch_.originAndStep.xy + s * patch_.originAndStep.z;
    precise vec2 metres = (demSample - u_cameraSampleFraction) * u_sampleSpacingM;
    precise float z = heightM - u_cameraHeightM;
    return vec3(metres.x, -metres.y, z);  // rows run south: +row is −y
}
