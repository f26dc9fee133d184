// The plane's side of the patch draws (runtime/surface PlaneSurface): where a patch lies, in
// the pyramid's map frame (x east, y north, z up), camera-relative in float without ever
// forming a map-sized coordinate; the bound on how many pixels a metre of error covers over a
// set of blocks (their axis-aligned box); the frustum test of blocks and skirts; the DEM's
// edge. A record's placement0 holds the patch's north-west DEM sample minus the anchor sample
// (xy; the anchor is the DEM sample at or before the camera) and DEM samples per patch sample
// (z, 2^(finest − level)); runtime/draw PatchInstance.cpp writes it.
#ifndef SURFACE_PLANE_GLSL
#define SURFACE_PLANE_GLSL

#include "terrain_heights.glsl"
#include "terrain_patches.glsl"
#include "terrain_primitives.glsl"

// The plane's coarse stage splits at half of ε (LodOptions::defaultCoarseShare): every edge
// meets ε with Err(P) included.
const bool kCoarseStageTakesWholeEpsilon = false;

// DEM sample (minus the anchor) of patch sample `s`: exact integers near the camera.
vec2 terrainDemSample(PatchInstance patch_, vec2 s) {
    precise vec2 demSample = patch_.placement0.xy + s * patch_.placement0.z;
    return demSample;
}

// Camera-relative metres of patch sample `s` (integers, apron excluded) at height h.
// Every term up to the subtraction of the camera's fraction is an integer, exact in float
// within 2^24 samples of the camera, so a DEM sample gets bit-identical coordinates from
// every patch and level that holds it: vertices shared by neighbours meet exactly, and
// `precise` keeps the compiler from fusing the operations differently at different uses.
vec3 terrainPositionM(PatchInstance patch_, vec2 s, float heightM) {
    precise vec2 demSample = patch_.placement0.xy + s * patch_.placement0.z;
    precise vec2 metres = (demSample - u_frame.planeCamera.xy) * u_frame.planeSpacing.xy;
    precise float z = heightM - u_frame.planeCamera.z;
    return vec3(metres.x, -metres.y, z);  // rows run south: +row is −y
}

// Metres between two of the patch's samples, east and south.
vec2 patchSampleSpacingM(PatchInstance patch_) {
    return u_frame.planeSpacing.xy * patch_.placement0.z;
}

// A vertex: patch sample `s` at height h, lowered by `dropM` (a skirt's); `up` the vertical.
vec3 surfacePositionM(PatchInstance patch_, vec2 s, float h, float dropM, out vec3 up) {
    up = vec3(0.0, 0.0, 1.0);
    // Blocks have no drop; a skirt's top row (drop 0) is exactly the patch's edge.
    precise vec3 position = terrainPositionM(patch_, s, h);
    position.z = position.z - dropM;
    return position;
}

// The shading normal of slopes `slope` (metres of height per patch sample, along the samples'
// x, east, and y, south).
vec3 surfaceNormalFromSlopes(PatchInstance patch_, vec2 slope, vec3 up) {
    vec2 metresPerSample = patchSampleSpacingM(patch_);
    return normalize(vec3(-slope.x / metresPerSample.x, slope.y / metresPerSample.y, 1.0));
}

// The shading normal at tile sample `texel`: central differences, which the one-sample apron
// makes available on the patch border too. Rows run south: +row is −y in the world.
vec3 surfaceShadingNormal(PatchInstance patch_, vec2 texel, float mode, vec3 up) {
    int layer = patch_.layerLevel.x;
    ivec2 t = ivec2(texel);
    vec2 metresPerSample = patchSampleSpacingM(patch_);
    float dx = heightAt(t + ivec2(1, 0), layer) - heightAt(t - ivec2(1, 0), layer);
    float dy = heightAt(t - ivec2(0, 1), layer) - heightAt(t + ivec2(0, 1), layer);
    return normalize(vec3(-dx / (2.0 * metresPerSample.x), -dy / (2.0 * metresPerSample.y), 1.0));
}

// Where the fragment stage clips the DEM's overhang: the DEM sample under patch sample s.
vec2 surfaceDemSample(PatchInstance patch_, vec2 s) { return terrainDemSample(patch_, s); }

// Where the imagery is looked up for patch sample `s` (terrain_imagery.glsl): the patch's
// (u, v).
vec2 surfaceImageryUv(PatchInstance patch_, vec2 s) { return s / float(u_frame.tessellation.z); }

// An upper bound, in pixels per metre, on the on-screen length of any vertical segment in
// the box [lo, hi] (camera-relative metres); the derivation is verticalErrorPxPerM's
// (EdgeTessellation.h). It replaces Yusov's proj(e_c^(d),−, e_c^(d),+) at the edge centre
// (§5), which points of the block nearer the camera exceed.
float verticalErrorPxPerM(vec3 drawnLo, vec3 drawnHi) {
    mat4 lodViewProjection = u_frame.lodViewProjection;
    // Relative to the LOD camera.
    vec3 lo = drawnLo + u_frame.lodOffsetM.xyz, hi = drawnHi + u_frame.lodOffsetM.xyz;
    float nearM = lodViewProjection[3].z;  // Camera::projection: z_clip = near
    float depthMin = 3.0e38;
    vec2 ndcLo = vec2(3.0e38), ndcHi = vec2(-3.0e38);
    for (int i = 0; i < 8; ++i) {
        vec3 corner = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y,
                           (i & 4) != 0 ? hi.z : lo.z);
        vec4 clip = lodViewProjection * vec4(corner, 1.0);
        depthMin = min(depthMin, clip.w);
        vec2 ndc = clip.xy / clip.w;
        ndcLo = min(ndcLo, ndc);
        ndcHi = max(ndcHi, ndc);
    }
    if (!(depthMin > 0.0)) {  // the box reaches behind the camera: the screen bounds it
        ndcLo = vec2(-1.0);
        ndcHi = vec2(1.0);
    }
    ndcLo = clamp(ndcLo, -1.0, 1.0);
    ndcHi = clamp(ndcHi, -1.0, 1.0);
    vec4 a = lodViewProjection[2];  // the clip-space image of e_z
    vec2 halfViewport = 0.5 * u_frame.screen.xy;
    float largest = 0.0;
    for (int i = 0; i < 4; ++i) {
        vec2 ndc = vec2((i & 1) != 0 ? ndcHi.x : ndcLo.x, (i & 2) != 0 ? ndcHi.y : ndcLo.y);
        largest = max(largest, length((a.xy - ndc * a.w) * halfViewport));
    }
    // A point in the frustum has |p| ≤ w · √(1 + tan²x + tan²y), and the rows of the
    // projection's x and y are the camera's right and up over tan x and tan y.
    vec3 rowX = vec3(lodViewProjection[0].x, lodViewProjection[1].x, lodViewProjection[2].x);
    vec3 rowY = vec3(lodViewProjection[0].y, lodViewProjection[1].y, lodViewProjection[2].y);
    float diagonal = sqrt(1.0 + 1.0 / dot(rowX, rowX) + 1.0 / dot(rowY, rowY));
    vec3 outside = max(max(lo, -hi), vec3(0.0));  // camera at the origin
    float depthOfDistance = length(outside) / diagonal;
    return largest / max(max(depthMin, depthOfDistance), nearM);
}

// The camera-relative box of blocks first..last (inclusive) of the patch: their footprint,
// and their heights (blocksHeightRangeM) reaching `belowM` further down and `aboveM` further up.
void blocksBoxM(PatchInstance patch_, ivec2 first, ivec2 last, float belowM, float aboveM,
                out vec3 lo, out vec3 hi) {
    int blockQuads = u_frame.tessellation.y;
    // The north-west corner at the lowest height, the south-east one at the highest:
    // together they span the box. Rows run south, so the north-west corner has the larger y.
    vec2 range = blocksHeightRangeM(patch_, first, last);
    vec3 nw = terrainPositionM(patch_, vec2(first * blockQuads), range.x);
    vec3 se = terrainPositionM(patch_, vec2((last + 1) * blockQuads), range.y);
    lo = vec3(nw.x, se.y, nw.z - belowM);
    hi = vec3(se.x, nw.y, se.z + aboveM);
}

// Pixels a metre of error covers at most over blocks first..last, their heights widened by
// `widenM` both ways (the full-resolution surface, where an error's segment ends, may lie
// that far beyond the patch's samples).
float blocksPxPerM(PatchInstance patch_, ivec2 first, ivec2 last, float widenM) {
    vec3 lo, hi;
    blocksBoxM(patch_, first, last, widenM, widenM, lo, hi);
    return verticalErrorPxPerM(lo, hi);
}

// Whether the box [lo, hi] (camera-relative metres) lies entirely outside one plane of the
// frustum. Conservative: the box must clear the plane by a margin that covers float
// rounding of the box and planes, so nothing visible is ever discarded.
bool outsideFrustum(vec3 lo, vec3 hi) {
    for (int i = 0; i < 5; ++i) {
        vec4 plane = u_frame.frustumPlanes[i];
        vec3 far = mix(lo, hi, greaterThanEqual(plane.xyz, vec3(0.0)));  // furthest along n
        float marginM = 0.05 + 1.0e-5 * (abs(far.x) + abs(far.y) + abs(far.z));
        if (dot(plane.xyz, far) + plane.w < -marginM) return true;
    }
    return false;
}

// Whether blocks first..last of the patch, reaching `dropM` further down (a skirt's drop; 0
// for blocks themselves), lie outside the frustum.
bool blocksOutsideFrustum(PatchInstance patch_, ivec2 first, ivec2 last, float dropM) {
    vec3 lo, hi;
    blocksBoxM(patch_, first, last, dropM, 0.0, lo, hi);
    return outsideFrustum(lo, hi);
}

// Whether `block` lies wholly beyond the DEM's extent (in a patch overhanging its right
// or bottom edge): it would draw only clamped copies of the edge.
bool blockBeyondExtent(PatchInstance patch_, ivec2 block) {
    vec2 first = terrainDemSample(patch_, vec2(block * u_frame.tessellation.y));
    return any(greaterThan(first, u_frame.demExtent.zw));
}

// Whether the skirt hanging from edge `edge` (GL order: west, north, east, south) of border
// block `block` lies along the DEM's own edge: no patch lies beyond it, so there is no crack
// for it to hide, and it would show as a wall hanging below the data's outline (issue 46,
// "exact data edges"; on a needle field, seen between the needles, up to 21 px tall).
bool skirtAlongSurfaceEdge(PatchInstance patch_, ivec2 block, int edge) {
    ivec2 a, b;
    terrainEdgeEnds(edge, a, b);
    vec2 onEdge = terrainDemSample(patch_, vec2((block + a) * u_frame.tessellation.y));
    const float kHalf = 0.5;  // samples: the edge's coordinates are whole samples
    return edge == 0   ? onEdge.x <= u_frame.demExtent.x + kHalf
           : edge == 1 ? onEdge.y <= u_frame.demExtent.y + kHalf
           : edge == 2 ? onEdge.x >= u_frame.demExtent.z - kHalf
                       : onEdge.y >= u_frame.demExtent.w - kHalf;
}

#endif  // SURFACE_PLANE_GLSL
