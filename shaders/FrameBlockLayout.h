// FrameBlockLayout: the per-frame parameters of the patch draws (the terrain draw on either
// surface and the comparison methods' draws) in one uniform block whose layout is defined here
// once, for C++ (runtime/draw FrameBlock.h expands it into a struct) and GLSL
// (terrain_frame.glsl expands it into the block). Every member is a vec4, an ivec4, a mat4 or an array of vec4,
// so std140 lays them out exactly as C++ does: 16-byte aligned, no padding. Only #define and
// comments here (Bindings.h says why).
#ifndef TERRAIN_FRAME_BLOCK_LAYOUT_H
#define TERRAIN_FRAME_BLOCK_LAYOUT_H

// X(type, name): MAT4, VEC4, IVEC4 members; VEC4_ARRAY(name, count).
#define TERRAIN_FRAME_BLOCK_MEMBERS(MAT4, VEC4, IVEC4, VEC4_ARRAY)                                 \
    /* Camera-relative metres to clip space. */                                                    \
    MAT4(viewProjection)                                                                           \
    /* The camera whose view decides the tessellation (TerrainStyle::lodCamera; by default  */     \
    /* the drawn one): its view-projection, relative to it.                                  */    \
    MAT4(lodViewProjection)                                                                        \
    /* The view frustum (left, right, bottom, top, near), camera-relative, normals inward:   */    \
    /* dot(n, p) + w >= 0 inside.                                                            */    \
    VEC4_ARRAY(frustumPlanes, 5)                                                                   \
    /* xyz: the drawn camera's position minus the LOD camera's, metres.                      */    \
    VEC4(lodOffsetM)                                                                               \
    /* x, y: the viewport, pixels; z: ε, pixels; w: the near plane, metres.                  */   \
    VEC4(screen)                                                                                   \
    /* x: pixels a metre at unit distance, at most, anywhere in the frustum (the globe's     */    \
    /* bound: f · (1 + tan²(fovX/2) + tan²(fovY/2))); y: pixels a metre at unit depth on     */ \
    /* the view axis (Camera::errorScale, the comparison methods' γ).                        */   \
    VEC4(pixelsPerMetre)                                                                           \
    /* x: tessellation blocks per patch side, y: quads a block side, z: quads a patch side,  */    \
    /* w: the fixed simplification d (−1: error-driven factors).                             */  \
    IVEC4(tessellation)                                                                            \
    /* x: discard blocks and skirts outside the frustum (1) or not (0), y: the debug view    */    \
    /* (TerrainDebugView), z: imagery layers drawn (0: none), w: imagery lit by the sun (1)  */    \
    /* or drawn as it is (0: its shadows are baked in).                                      */    \
    IVEC4(options)                                                                                 \
    /* The plane: xy the camera's DEM sample minus the anchor sample, z its height, metres;  */    \
    /* the anchor is the DEM sample at or before the camera, so these are small.             */    \
    VEC4(planeCamera)                                                                              \
    /* The plane: xy metres per DEM sample, east and south.                                  */    \
    VEC4(planeSpacing)                                                                             \
    /* The DEM's first (xy) and last (zw) sample minus the anchor: nothing beyond is drawn   */    \
    /* (±1e30 on the globe, which has no edge).                                              */   \
    VEC4(demExtent)                                                                                \
    /* xyz: towards the sun, unit length, world frame.                                       */    \
    VEC4(sunDirection)                                                                             \
    /* xy: the heights the hypsometric tint spans, metres; z: sea level, metres; w: 1 where  */    \
    /* what lies at or below it is drawn as water (the globe), 0 where not (the plane).      */    \
    VEC4(heightRange)                                                                              \
    /* rgb: the sky and fog colour; w: the fog density per metre (0: none).                  */    \
    VEC4(sky)                                                                                      \
    /* The imagery layers' opacities, by the manifest's index (options.z of them drawn).    */     \
    VEC4(imageryOpacity)                                                                           \
    /* The imagery layers in the order they are composited, bottom first: manifest indices.  */    \
    IVEC4(imageryOrder)                                                                            \
    /* x: the anisotropy the imagery tiles' sampler filters with (1: trilinear only).      */      \
    VEC4(imagerySampling)

#endif  // TERRAIN_FRAME_BLOCK_LAYOUT_H
