// The surface of the patch draw: the globe's (surface_globe.glsl) when the program is built
// with TERRAIN_SURFACE_GLOBE, else the plane's (surface_plane.glsl). Both define the same
// functions (surfacePositionM, surfaceShadingNormal, surfaceDemSample, blocksPxPerM,
// blocksOutsideFrustum, blockBeyondExtent, skirtAlongSurfaceEdge,
// kCoarseStageTakesWholeEpsilon); the stages that
// include this are written once for both surfaces.
#ifndef TERRAIN_SURFACE_GLSL
#define TERRAIN_SURFACE_GLSL

#ifdef TERRAIN_SURFACE_GLOBE
#include "surface_globe.glsl"
#else
#include "surface_plane.glsl"
#endif

#endif  // TERRAIN_SURFACE_GLSL
