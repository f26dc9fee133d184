// The terrain draw's shared definitions: the per-instance record (one per drawn patch,
// std430, matches terrain::runtime::PatchInstance in TerrainRenderer.h), the primitives of
// an instance, and the one function that places a patch sample relative to the camera.
//
// Primitives of an instance (quad patches of 4 vertices, vertex id = 4 · primitive + corner):
//   [0, K²)         tessellation block (bx, by) = (p % K, p / K), row-major, K = u_blocksPerSide;
//   [K², K² + 4K)   skirt q = p − K²: hangs from edge e = q / K of border block i = q % K,
//                   e in GL's outer-level order (see terrainSkirtBlock).
// Block domain: u runs east along the patch's columns, v south along its rows, so
// gl_TessLevelOuter[0] is the block's west edge (u = 0), [1] north (v = 0), [2] east
// (u = 1), [3] south (v = 1). Skirt domain: u along the edge, v down (0: the edge).

struct PatchInstance {
    // x, y: the patch's north-west sample minus the anchor sample (u_cameraSampleFraction),
    // in DEM samples (x east, y south); z: DEM samples per patch sample, 2^(finest − level).
    vec4 originAndStep;
    // x: Err(P), metres (Yusov §4); y: skirt depth, metres: the CPU's bound on the Λ of
    // any neighbouring patch (SkirtDepth.h); z, w: the patch's min and max height, metres.
    vec4 errors;
    ivec4 layerLevel;  // x: texture-array layer, y: level
};

layout(std430, binding = TERRAIN_BINDING_PATCH_INSTANCES) readonly buffer PatchInstances {
    PatchInstance u_instances[];
};

uniform int u_blocksPerSide;        // K
uniform int u_blockQuads;           // B, quads along a block side
uniform vec2 u_cameraSampleFraction;  // camera x, y in DEM samples minus the anchor, [0, 1)
uniform vec2 u_sampleSpacingM;      // metres per DEM sample, east and south
uniform float u_cameraHeightM;
// The DEM's extent in DEM samples minus the anchor: its first (0, 0) and last (width − 1,
// height − 1) sample. A level's last patches overhang it (they are whole patches of
// clamped samples): nothing beyond it is data, and nothing beyond it is drawn.
uniform vec2 u_demFirstSample;
uniform vec2 u_demLastSample;

const ivec2 kEdgeNeighbour[4] = ivec2[](ivec2(-1, 0), ivec2(0, -1), ivec2(1, 0), ivec2(0, 1));

// The border block a skirt hangs from: edge e (GL order) of the i-th block along that side.
ivec2 terrainSkirtBlock(int edge, int i) {
    int last = u_blocksPerSide - 1;
    return edge == 0 ? ivec2(0, i) : edge == 1 ? ivec2(i, 0) : edge == 2 ? ivec2(last, i)
                                                                         : ivec2(i, last);
}

// Ends of a block's edge in block corners, in the order of the domain coordinate that runs
// along it (u for north/south, v for west/east).
void terrainEdgeEnds(int edge, out ivec2 a, out ivec2 b) {
    a = edge == 2 ? ivec2(1, 0) : edge == 3 ? ivec2(0, 1) : ivec2(0, 0);
    b = (edge == 0 || edge == 2) ? a + ivec2(0, 1) : a + ivec2(1, 0);
}

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
