// Patch draws, fragment stage: the shaded view (terrain_shading.glsl, shared with the
// reference renderers so the two differ only where geometry or normals do) or a debug colour
// (patch level, block tessellation factor) under the same sun and fog. Fragments beyond the
// DEM's extent — the overhang of a level's last patches on the plane — are discarded.
#include "Bindings.h"
#include "terrain_frame.glsl"
#include "terrain_shading.glsl"
#if defined(TERRAIN_FRAGMENT_NORMALS) || defined(TERRAIN_SURFACE_GLOBE)
// Only the tessellated draw (terrain.tese) defines either: the other methods' stages write
// neither the instance nor the imagery's (u, v).
#include "terrain_surface.glsl"
layout(location = 10) in vec2 i_imageryUv;  // surfaceImageryUv
#endif

layout(location = 0) in vec3 i_fromCameraM;
layout(location = 1) in vec3 i_normal;
layout(location = 2) in float i_heightM;
layout(location = 3) flat in int i_level;
layout(location = 4) flat in int i_tessFactor;
layout(location = 5) in vec2 i_demSample;
layout(location = 9) flat in int i_patch;
layout(location = TERRAIN_FRAG_COLOR) out vec4 o_color;
#ifdef TERRAIN_IMAGERY_TEXELS_PER_PIXEL
// The program variant TerrainStyle::imageryTexelsPerPixel draws with: the draped imagery's
// texels per pixel at the level it samples (terrain_imagery.glsl), into an R32F target; 0
// where no imagery shows.
layout(location = TERRAIN_FRAG_IMAGERY_TEXELS_PER_PIXEL) out float o_imageryTexelsPerPixel;
#endif

#ifdef TERRAIN_FRAGMENT_NORMALS
// The terrain draw shades with the normal of the patch's own full-resolution mesh at the
// fragment rather than the one interpolated between the drawn vertices: shading then does not
// depend on the tessellation, so a block or a coarse cell (runtime/lod CoarseCells.h) that
// changes level changes the geometry only, within its bound, and not the light across it (and
// fine data drawn with few vertices does not shade as a hatching of its triangles). The
// reference renderers' mesh is the same one at the finest level, so at full resolution both
// shade alike. The normals at the samples are the surface's (surfaceShadingNormal: the map
// frame's on the plane, tilted from the ellipsoid normal on the globe). Where a pixel spans
// several samples the normal is filtered to its footprint (terrain_footprint.glsl), as the
// reference's is.
#include "terrain_footprint.glsl"
#include "terrain_imagery.glsl"

layout(location = 6) in vec2 i_patchSample;  // the patch's samples, apron excluded
layout(location = 8) in vec3 i_up;

vec3 sampleNormal(PatchInstance patch_, ivec2 s) {
    return surfaceShadingNormal(patch_, tileTexel(patch_.texelMap, vec2(s)), patch_.texelMap.w,
                                i_up);
}

// The normal of the full-resolution mesh at patch sample p: its cell split along the
// north-west–south-east diagonal, as the reference renderer splits it, and the corners'
// normals blended barycentrically, as the rasteriser blends the reference's vertices'.
vec3 fragmentNormal(vec2 p) {
    PatchInstance patch_ = u_instances[i_patch];
    int lastCell = u_frame.tessellation.z - 1;  // N − 1 cells a side
    ivec2 cell = clamp(ivec2(floor(p)), ivec2(0), ivec2(lastCell));
    vec2 f = clamp(p - vec2(cell), 0.0, 1.0);
    vec3 a = sampleNormal(patch_, cell);
    vec3 d = sampleNormal(patch_, cell + ivec2(1, 1));
    if (f.x >= f.y) {
        vec3 b = sampleNormal(patch_, cell + ivec2(1, 0));
        return a + (b - a) * f.x + (d - b) * f.y;
    }
    vec3 c = sampleNormal(patch_, cell + ivec2(0, 1));
    return a + (d - c) * f.x + (c - a) * f.y;
}

float sampleHeight(PatchInstance patch_, ivec2 s) {
    return tileHeight(tileTexel(patch_.texelMap, vec2(s)), patch_.texelMap.w, patch_.layerLevel.x);
}

// The full-resolution mesh's height at patch sample p, on fragmentNormal's triangles, and its
// slope there (per sample, x and y): the tint (and where the sea ends) follows the patch's
// samples, not its tessellation, so a coarsely tessellated block does not draw a coast or a
// data edge in teeth of its cells.
vec3 fragmentHeight(vec2 p) {
    PatchInstance patch_ = u_instances[i_patch];
    int lastCell = u_frame.tessellation.z - 1;
    ivec2 cell = clamp(ivec2(floor(p)), ivec2(0), ivec2(lastCell));
    vec2 f = clamp(p - vec2(cell), 0.0, 1.0);
    float a = sampleHeight(patch_, cell);
    float d = sampleHeight(patch_, cell + ivec2(1, 1));
    if (f.x >= f.y) {
        float b = sampleHeight(patch_, cell + ivec2(1, 0));
        return vec3(a + (b - a) * f.x + (d - b) * f.y, b - a, d - b);
    }
    float c = sampleHeight(patch_, cell + ivec2(0, 1));
    return vec3(a + (d - c) * f.x + (c - a) * f.y, d - c, c - a);
}

#endif

// Interpolation may put the DEM's own edge a hair outside it.
const float kEdgeToleranceSamples = 1.0e-3;

vec3 levelColor(int level) {
    const vec3 palette[6] = vec3[](vec3(0.90, 0.30, 0.25), vec3(0.95, 0.65, 0.20),
                                   vec3(0.85, 0.85, 0.25), vec3(0.35, 0.75, 0.35),
                                   vec3(0.30, 0.60, 0.90), vec3(0.60, 0.40, 0.85));
    return palette[level % 6];
}

// Coarse to fine, cold to hot: factor 1 dark blue, 2 blue, 4 cyan, 8 green, 16 yellow,
// 32 orange, 64 and more red.
vec3 tessFactorColor(int factor) {
    const vec3 palette[7] = vec3[](vec3(0.15, 0.15, 0.55), vec3(0.20, 0.40, 0.95),
                                   vec3(0.20, 0.80, 0.90), vec3(0.30, 0.80, 0.30),
                                   vec3(0.95, 0.90, 0.25), vec3(0.95, 0.55, 0.15),
                                   vec3(0.90, 0.20, 0.20));
    return palette[clamp(findMSB(max(factor, 1)), 0, 6)];
}

// The patch-id view: draw instance + 1 in the colour's bytes, R low, unlit and unfogged, so
// the image decodes exactly (runtime/truth BoundaryArtefacts.h, patchIdsOf); 0 is no patch.
vec3 patchIdColor(int instance) {
    int id = instance + 1;
    return vec3(float(id & 255), float((id >> 8) & 255), float((id >> 16) & 255)) / 255.0;
}

void main() {
#ifdef TERRAIN_IMAGERY_TEXELS_PER_PIXEL
    o_imageryTexelsPerPixel = 0.0;
#endif
#ifdef TERRAIN_FRAGMENT_NORMALS
    float footprint = sampleFootprint(i_patchSample);
    // Before the discard, as derivatives need.
    vec2 sampleDx = dFdx(i_patchSample), sampleDy = dFdy(i_patchSample);
    vec2 imageryDx = dFdx(i_imageryUv), imageryDy = dFdy(i_imageryUv);
#endif
    if (any(lessThan(i_demSample, u_frame.demExtent.xy - kEdgeToleranceSamples)) ||
        any(greaterThan(i_demSample, u_frame.demExtent.zw + kEdgeToleranceSamples))) {
        discard;
    }
#ifdef TERRAIN_SURFACE_GLOBE
    // A native tile draws only the ground it owns; the face patches draw the rest
    // (surfaceOwnsGround).
    if (!surfaceOwnsGround(u_instances[i_patch], i_imageryUv)) discard;
#endif
#ifdef TERRAIN_FRAGMENT_NORMALS
    // From two samples of footprint up the filtered normal alone shows (footprintNormal's
    // blend weight is 1): the mesh's normal is not worth its texel fetches there.
    vec3 meshNormal = footprint < 2.0 ? fragmentNormal(i_patchSample) : vec3(0.0, 0.0, 1.0);
    FootprintSurface ground = footprintSurface(i_patch, i_patchSample, footprint);
    vec3 normal = footprintNormal(i_patch, ground, meshNormal, normalize(i_up));
#else
    vec3 normal = i_normal;
#endif
    TerrainShading shading = TerrainShading(u_frame.sunDirection.xyz, u_frame.heightRange.xy,
                                            u_frame.sky.rgb, u_frame.sky.w, u_frame.heightRange.zw);
    int debugView = u_frame.options.y;  // TerrainDebugView: 0 shaded, 1 level, 2 tess, 3 patch
    if (debugView == 3) {
        o_color = vec4(patchIdColor(i_patch), 1.0);
        return;
    }
    if (debugView == 0) {
#ifdef TERRAIN_FRAGMENT_NORMALS
        // The coast blends over the mesh's own change across the pixel, from its slope and
        // the interpolated sample's derivatives (a computed height's own derivative is not
        // defined beside a discard, and a helper lane's fetches may lie off the patch).
        // Where the pixel spans several samples the height and slope are the footprint's,
        // as the normal is: the tint and the coast then do not depend on the level drawn.
        vec3 mesh = fragmentHeight(i_patchSample);
        float heightM = mix(mesh.x, ground.heightM, ground.weight);
        float coastWidthM =
            heightAcrossPixel(mix(mesh.yz, ground.slope, ground.weight), sampleDx, sampleDy);
#else
        float heightM = i_heightM;
        float coastWidthM = fwidth(i_heightM);
#endif
        vec3 color = terrainShade(shading, normal, heightM, coastWidthM, i_fromCameraM);
#ifdef TERRAIN_FRAGMENT_NORMALS
        // Imagery over the tint (terrain_imagery.glsl), at the patch's (u, v) (a native
        // tile's: on the face patch it drapes; surfaceImageryUv). Lit as the land is, or drawn
        // as it is, fogged alike.
        if (u_frame.options.z > 0) {
            vec4 imagery = drapedImagery(i_patch, i_imageryUv, imageryDx, imageryDy);
#ifdef TERRAIN_IMAGERY_TEXELS_PER_PIXEL
            o_imageryTexelsPerPixel =
                imageryTexelsPerPixel(i_patch, i_imageryUv, imageryDx, imageryDy);
#endif
            if (imagery.a > 0.0) {
                float ambient = u_frame.options.w != 0 ? 0.25 : 1.0;
                vec3 draped = terrainLitColor(shading, imagery.rgb, normal, i_fromCameraM, ambient);
                color = mix(color, draped, imagery.a);
            }
        }
#endif
        o_color = vec4(color, 1.0);
        return;
    }
    vec3 base = debugView == 1 ? levelColor(i_level) : tessFactorColor(i_tessFactor);
    o_color = vec4(terrainShadeColor(shading, base, normal, i_fromCameraM), 1.0);
}
