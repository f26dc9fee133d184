// Imagery draped on the terrain (issue 47), fragment stage: each pixel walks its patch's tree
// of imagery tiles (runtime/lod ImagerySelection.h) from the patch's root down to the level
// whose interior texels are no larger than the pixel's footprint, and samples that tile's
// mips with the footprint's derivatives (trilinear, anisotropic: the sampler's). The level
// follows the pixel, not the patch: two patches of different levels meet on the same texels,
// and a tile's mip 1 holds what its parent's mip 0 does, so the level's change across the
// view is continuous. A tile's 4-texel border holds its neighbours' texels
// (io/pyramid ImageryTile.h), so filtering near its edge reads what the neighbour would.
// Layers are composited bottom first (the manifest's order, or the one the style gives), each
// over those before by its alpha times its opacity.
#ifndef TERRAIN_IMAGERY_GLSL
#define TERRAIN_IMAGERY_GLSL

#include "Bindings.h"
#include "terrain_frame.glsl"

struct ImageryNode {
    ivec4 node;  // x: texture-array layer (-1: none), y: children entry (-1: none), z: level
    vec4 map;    // the node's (u, v) on its layer's tile: map.xy + (u, v) · map.z
};
struct ImageryRoot {
    vec2 offset;  // the patch's (u, v) on its root tile: offset + (u, v) · scale
    float scale;
    int node;     // -1: the layer draws nothing on this patch
};

layout(std430, binding = TERRAIN_BINDING_IMAGERY_NODES) readonly buffer ImageryNodes {
    ImageryNode u_imageryNodes[];
};
layout(std430, binding = TERRAIN_BINDING_IMAGERY_CHILDREN) readonly buffer ImageryChildren {
    ivec4 u_imageryChildren[];
};
layout(std430, binding = TERRAIN_BINDING_IMAGERY_ROOTS) readonly buffer ImageryRoots {
    ImageryRoot u_imageryRoots[];
};
layout(binding = TERRAIN_BINDING_IMAGERY_TILES) uniform sampler2DArray u_imageryTiles;

const float kImageryTileTexels = 256.0;  // io::kImageryTileTexels
const float kImageryBorderTexels = 4.0;
const float kImageryInteriorTexels = 248.0;
const int kMaxImageryDepth = 30;

// Where layer `layer`'s texels for the patch's (u, v) `uv` lie, whose change across the pixel
// is dx, dy: the tile of the level whose interior texels are no larger than the footprint, the
// texture coordinate within it and the gradients textureGrad is given (found false: the layer
// draws nothing there).
struct ImageryLookup {
    bool found;
    vec3 coord;  // (s, t, texture-array layer)
    vec2 gradX;  // the coordinate's change across the pixel, in the tile's (s, t)
    vec2 gradY;
};

ImageryLookup imageryLookup(int instance, int layer, int layerCount, vec2 uv, vec2 dx, vec2 dy) {
    ImageryLookup none = ImageryLookup(false, vec3(0.0), vec2(0.0), vec2(0.0));
    ImageryRoot root = u_imageryRoots[instance * layerCount + layer];
    if (root.node < 0) return none;
    vec2 p = clamp(root.offset + uv * root.scale, 0.0, 1.0);
    vec2 px = dx * root.scale, py = dy * root.scale;
    float lengthX = length(px), lengthY = length(py);
    // The sampler's anisotropic filter covers the long side up to imagerySampling.x times the
    // short one: the tile is chosen for what is left (as the hardware chooses its mip).
    float anisotropy = u_frame.imagerySampling.x;
    float footprint = max(max(lengthX, lengthY) / anisotropy, min(lengthX, lengthY));
    // The depth below the root whose interior texels are no larger than the footprint.
    float wanted = -log2(max(footprint * kImageryInteriorTexels, 1.0e-30));
    int depth = clamp(int(ceil(wanted)), 0, kMaxImageryDepth);
    int n = root.node;
    float scale = 1.0;
    for (int d = 0; d < depth; ++d) {
        int children = u_imageryNodes[n].node.y;
        if (children < 0) break;
        vec2 quadrant = step(vec2(0.5), p);
        n = u_imageryChildren[children][int(quadrant.y) * 2 + int(quadrant.x)];
        p = clamp(p * 2.0 - quadrant, 0.0, 1.0);
        scale *= 2.0;
    }
    ImageryNode node = u_imageryNodes[n];
    if (node.node.x < 0) return none;
    vec2 texel = kImageryBorderTexels + (node.map.xy + p * node.map.z) * kImageryInteriorTexels;
    float k = scale * node.map.z * kImageryInteriorTexels / kImageryTileTexels;
    return ImageryLookup(true, vec3(texel / kImageryTileTexels, float(node.node.x)), px * k,
                         py * k);
}

// Layer `layer`'s colour (linear RGB, straight alpha) at the patch's (u, v) `uv`, whose
// change across the pixel is dx, dy.
vec4 imageryLayerColor(int instance, int layer, int layerCount, vec2 uv, vec2 dx, vec2 dy) {
    ImageryLookup at = imageryLookup(instance, layer, layerCount, uv, dx, dy);
    if (!at.found) return vec4(0.0);
    return textureGrad(u_imageryTiles, at.coord, at.gradX, at.gradY);
}

// sRGB's encoding of a linear colour (the tiles are sampled linear, filtered as light adds;
// the rest of the look is written in encoded values).
vec3 imageryEncoded(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// Every drawn layer composited: rgb encoded, a the coverage (0: no imagery, the tint shows).
vec4 drapedImagery(int instance, vec2 uv, vec2 dx, vec2 dy) {
    int layerCount = u_frame.options.z;
    vec3 premultiplied = vec3(0.0);
    float alpha = 0.0;
    for (int drawn = 0; drawn < layerCount; ++drawn) {
        int l = u_frame.imageryOrder[drawn];
        float opacity = u_frame.imageryOpacity[l];
        if (opacity <= 0.0) continue;
        vec4 c = imageryLayerColor(instance, l, layerCount, uv, dx, dy);
        float a = c.a * opacity;
        premultiplied = c.rgb * a + premultiplied * (1.0 - a);
        alpha = a + alpha * (1.0 - a);
    }
    return alpha > 0.0 ? vec4(imageryEncoded(premultiplied / alpha), alpha) : vec4(0.0);
}

#ifdef TERRAIN_IMAGERY_TEXELS_PER_PIXEL
// The debug measure (TerrainStyle::imageryTexelsPerPixel): the texels across the pixel of the
// tile level the draw samples, in the bottom drawn layer that shows there (the first, bottom
// first, with opacity and a texel not wholly transparent): the longer of the two gradients
// textureGrad is given, in that tile's own texels, which is the ρ the hardware takes the log2
// of for its level of detail (within the tile's mips). 0 where no layer shows.
float imageryTexelsPerPixel(int instance, vec2 uv, vec2 dx, vec2 dy) {
    int layerCount = u_frame.options.z;
    for (int drawn = 0; drawn < layerCount; ++drawn) {
        int l = u_frame.imageryOrder[drawn];
        if (u_frame.imageryOpacity[l] <= 0.0) continue;
        ImageryLookup at = imageryLookup(instance, l, layerCount, uv, dx, dy);
        if (!at.found || textureGrad(u_imageryTiles, at.coord, at.gradX, at.gradY).a <= 0.0)
            continue;
        return kImageryTileTexels * max(length(at.gradX), length(at.gradY));
    }
    return 0.0;
}
#endif

#endif  // TERRAIN_IMAGERY_GLSL
