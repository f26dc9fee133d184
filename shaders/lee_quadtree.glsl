// Lee & Shin 2011, "Geometry splitting" (LodMethod::Lee2011): what the passes of the GPU
// quadtree share. The paper's geometry shader + stream output passes are compute passes
// here, each appending to lists with atomic counters; the counters (one per pass) and the
// indirect arguments of the next pass live in one buffer (GeometrySplittingStrategy.h).
// Coordinates are DEM samples (x east, y south) of the padded n × n grid, n = 2^d + 1.
// Defines from the program builder: LEE_MAX_PASSES, LEE_FORCE_SPLIT.
#include "Bindings.h"
#include "terrain_frame.glsl"

layout(std430, binding = TERRAIN_BINDING_LEE_COUNTERS) coherent buffer LeeCounters {
    uint c_nodes[LEE_MAX_PASSES];    // blocks entering vertex-splitting pass p; [0] = the root
    uint c_pending[LEE_MAX_PASSES];  // triangles entering triangle-splitting pass p
    uint c_leaves;                   // blocks drawn (leaves of the quadtree)
    uint c_triangles;                // triangles drawn
};

layout(binding = TERRAIN_BINDING_LEE_HEIGHTS) uniform sampler2D u_heightField;  // the raster
layout(binding = TERRAIN_BINDING_LEE_ROUGHNESS) uniform sampler2D u_roughness;  // n × n, σ
// Level l: min and max height of the blocks of half size 2^l, one texel per block.
layout(binding = TERRAIN_BINDING_LEE_RANGES) uniform sampler2D u_heightRanges;

uniform ivec2 u_rasterSize;  // width, height in samples
uniform int u_gridSide;      // n
uniform float u_thresholdPx;  // τ

float heightAt(ivec2 s) {
    return texelFetch(u_heightField, clamp(s, ivec2(0), u_rasterSize - 1), 0).r;
}

// Camera-relative metres of a sample at height h, as rtin.vert and reference.vert place it.
vec3 fromCamera(vec2 s, float h) {
    precise vec2 metres = (s - planeAnchorSample() - u_frame.planeCamera.xy) * u_frame.planeSpacing.xy;
    return vec3(metres.x, -metres.y, h - u_frame.planeCamera.z);
}

// A block with no area inside the raster (its north-west corner on or past the last
// column or row) is never created.
bool insideRaster(ivec2 northWest) { return all(lessThan(northWest, u_rasterSize - 1)); }

// The bounding sphere P of the block around c with half size h (Eq. 2), its heights
// included: the paper's sphere of the block's diagonal would cull peaks that stand in view.
vec4 blockSphere(ivec2 c, int h, int level) {
    vec2 range = texelFetch(u_heightRanges, (c - h) / (2 * h), level).rg;
    vec2 halfSizeM = float(h) * u_frame.planeSpacing.xy;
    float halfRange = 0.5 * (range.y - range.x);
    return vec4(fromCamera(vec2(c), 0.5 * (range.x + range.y)),
                sqrt(dot(halfSizeM, halfSizeM) + halfRange * halfRange));
}

// §3, Fig. 10: a block whose sphere lies outside the view frustum is not created.
bool sphereVisible(vec4 sphere) {
    for (int i = 0; i < 5; ++i) {
        if (dot(u_frame.frustumPlanes[i].xyz, sphere.xyz) + u_frame.frustumPlanes[i].w < -sphere.w) {
            return false;
        }
    }
    return true;
}

// Pixels between the projections of a and b; unbounded when either is behind the eye.
float projectedPx(vec3 a, vec3 b) {
    vec4 pa = u_frame.viewProjection * vec4(a, 1.0);
    vec4 pb = u_frame.viewProjection * vec4(b, 1.0);
    if (pa.w <= 0.0 || pb.w <= 0.0) return 1.0e30;
    return length((pa.xy / pa.w - pb.xy / pb.w) * 0.5 * u_frame.screen.xy);
}

// The LOD flag f of Eq. 2 for the block around c with half size h: 1 when the eye is inside
// its bounding sphere and σ ≠ 0, or when the largest screen-space error of its five points
// (Fig. 3: each point v and v' = v raised by σ, projected) reaches τ (Eq. 1).
bool lodFlag(ivec2 c, int h, int level) {
    float sigma = texelFetch(u_roughness, c, 0).r;
    if (sigma >= LEE_FORCE_SPLIT) return true;  // the block overhangs the raster
    if (sigma == 0.0) return false;
    vec4 sphere = blockSphere(c, h, level);
    if (length(sphere.xyz) - sphere.w < 0.0) return true;
    const ivec2 points[5] = ivec2[5](c, c + ivec2(h, 0), c - ivec2(h, 0), c + ivec2(0, h),
                                     c - ivec2(0, h));
    float maxPx = 0.0;
    for (int k = 0; k < 5; ++k) {
        vec3 v = fromCamera(vec2(points[k]), heightAt(points[k]));
        maxPx = max(maxPx, projectedPx(v, v + vec3(0.0, 0.0, sigma)));
    }
    return u_thresholdPx <= maxPx;
}
