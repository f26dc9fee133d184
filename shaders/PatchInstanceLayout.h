// PatchInstanceLayout: one drawn patch as the GPU reads it (std430, one record per instance of
// the patch draws), its layout defined here once for C++ (runtime/draw PatchInstance.h) and
// GLSL (terrain_patches.glsl), as FrameBlockLayout.h is. The first five vectors say where the patch
// lies, in its surface's terms (surface_plane.glsl, surface_globe.glsl); the rest is the
// same on both surfaces. Only #define and comments here (Bindings.h says why).
#ifndef TERRAIN_PATCH_INSTANCE_LAYOUT_H
#define TERRAIN_PATCH_INSTANCE_LAYOUT_H

// The members' comments line up with the continuations, by hand.
// clang-format off
#define TERRAIN_PATCH_INSTANCE_MEMBERS(VEC4, IVEC4)                                            \
    /* Where the patch lies, camera-relative (PlanePlacement, GlobePlacement).               */ \
    VEC4(placement0)                                                                           \
    VEC4(placement1)                                                                           \
    VEC4(placement2)                                                                           \
    VEC4(placement3)                                                                           \
    VEC4(placement4)                                                                           \
    /* x: Err(P), metres (Yusov §4); y: the skirt depth, metres (SkirtDepth.h); z, w: the    */ \
    /* patch's lowest and highest height, metres.                                            */ \
    VEC4(errors)                                                                               \
    /* λ(1..4) of a patch without a tile of its own (bare or virtual); 0 for a data patch.   */ \
    VEC4(bareBlockErrors)                                                                      \
    /* Patch sample s lies on tile sample xy + s · z (a virtual patch draws an ancestor's    */ \
    /* tile between its samples); w: 1 for a virtual patch. A data patch: (0, 0, 1, 0).      */ \
    VEC4(texelMap)                                                                             \
    /* x: quads along a coarse cell's side, 0 when the patch is drawn as blocks; y: the      */ \
    /* cells' Λ, metres (runtime/lod CoarseCells.h).                                         */ \
    VEC4(coarseCells)                                                                          \
    /* x: the texture-array layer (−1: no tile, the bare surface), y: the level (the face    */ \
    /* level on the globe), z, w: the patch's x, y at its level (the plane) or its cube face */ \
    /* and 0 (the globe).                                                                    */ \
    IVEC4(layerLevel)                                                                          \
    /* A native tile: the cells of the face patch it drapes where it owns the ground, x the  */ \
    /* low 32 bits, y the high (runtime/surface NativeOwnership.h); z, w the window's first  */ \
    /* cell. 0 for everything else.                                                          */ \
    IVEC4(nativeCells)
// clang-format on

#endif  // TERRAIN_PATCH_INSTANCE_LAYOUT_H
