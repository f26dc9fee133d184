// Binding points shared by C++ and GLSL: this file is valid in both languages.
// C++ includes it through terrain::programs' include path ("Bindings.h"); shaders include
// it with `#include "Bindings.h"`, which the program builder resolves. Only #define and
// comments here: anything else would stop being valid in one of the two languages.
// Each kind (vertex attribute, texture unit, storage block, fragment output) has its own
// numbering, so equal numbers across kinds do not collide.
#ifndef TERRAIN_BINDINGS_H
#define TERRAIN_BINDINGS_H

// Vertex attribute locations.
#define TERRAIN_ATTRIB_POSITION 0

// Fragment output locations.
#define TERRAIN_FRAG_COLOR 0
// The terrain draw's imagery texels per pixel (TerrainStyle::imageryTexelsPerPixel), and the
// reference draw's world height: the R32F attachment 1 of gl::Framebuffer.
#define TERRAIN_FRAG_IMAGERY_TEXELS_PER_PIXEL 1

// Texture units of the terrain draw (the GPU tile pool's texture arrays).
#define TERRAIN_BINDING_HEIGHTS 0
#define TERRAIN_BINDING_BLOCK_ERRORS 1
// Each block's lowest and highest sample (cache GpuTilePool::blockRanges): its own box.
#define TERRAIN_BINDING_BLOCK_RANGES 8
// Valdetaro et al. 2011 (LodMethod::Valdetaro2011): per tile HAM_max, h_max and its texel.
#define TERRAIN_BINDING_VALDETARO_TILES 2
// Lee & Shin 2011 (LodMethod::Lee2011): the full-resolution height field, the quadtree
// texture of roughness values and the blocks' height ranges (a mip chain).
#define TERRAIN_BINDING_LEE_HEIGHTS 3
#define TERRAIN_BINDING_LEE_ROUGHNESS 4
#define TERRAIN_BINDING_LEE_RANGES 5

// Ripolles et al. (LodMethod::Ripolles): the full-resolution height field, filtered
// (vertices fall between samples).
#define TERRAIN_BINDING_RIPOLLES_HEIGHTS 6

// Image units. Lee & Shin 2011: the flag of every block split this frame, at its centre.
#define TERRAIN_IMAGE_LEE_SPLIT_FLAGS 0

// Uniform blocks. The patch draws' per-frame parameters (FrameBlockLayout.h).
#define TERRAIN_BINDING_FRAME_BLOCK 0

// Shader storage blocks.
#define TERRAIN_BINDING_PATCH_INSTANCES 0
// Tessellation factors the terrain's control stage chose, one record per (instance,
// primitive): written only by programs built with TERRAIN_DEBUG_TESS_FACTORS (tests).
#define TERRAIN_BINDING_DEBUG_TESS_FACTORS 1
// Lee & Shin 2011's passes: their counters and indirect arguments, the pass's input and
// output lists, the leaf blocks and the final triangles.
#define TERRAIN_BINDING_LEE_COUNTERS 2
#define TERRAIN_BINDING_LEE_INPUT 3
#define TERRAIN_BINDING_LEE_OUTPUT 4
#define TERRAIN_BINDING_LEE_LEAVES 5
#define TERRAIN_BINDING_LEE_TRIANGLES 6
// Ripolles et al.'s steps: counters and indirect arguments, the current tessellation (leaf
// triangles; the next one is written by transform feedback), the triangle families and the
// free family slots.
#define TERRAIN_BINDING_RIPOLLES_COUNTERS 7
#define TERRAIN_BINDING_RIPOLLES_LEAVES 8
#define TERRAIN_BINDING_RIPOLLES_FAMILIES 10
#define TERRAIN_BINDING_RIPOLLES_FREE_SLOTS 11
#define TERRAIN_BINDING_RIPOLLES_FREED_SLOTS 12
// The tiles above each drawn patch's own that its footprint-filtered normals read
// (terrain_footprint.glsl, runtime/draw ShadingTiles.h): TERRAIN_SHADING_ANCESTORS per instance.
#define TERRAIN_BINDING_SHADING_TILES 9
#define TERRAIN_SHADING_ANCESTORS 8
// Imagery draped on the terrain (issue 47; runtime/lod ImagerySelection.h,
// terrain_imagery.glsl): the texture array of imagery tiles (a texture unit), the frame's
// listed tiles, their children and each drawn patch's roots (storage blocks), and how many
// layers one draw composites.
#define TERRAIN_BINDING_IMAGERY_TILES 7
#define TERRAIN_BINDING_IMAGERY_NODES 13
#define TERRAIN_BINDING_IMAGERY_CHILDREN 14
#define TERRAIN_BINDING_IMAGERY_ROOTS 15
#define TERRAIN_MAX_IMAGERY_LAYERS 4

#endif  // TERRAIN_BINDINGS_H
