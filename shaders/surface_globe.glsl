// The globe's side of the patch draws (runtime/surface GlobeSurface; DESIGN.md, "The globe"):
// where a patch sample lies on the WGS84 ellipsoid, camera-relative, in float only — the
// GLSL twin of io/globe SurfaceOffset.h, which holds the derivation and the test against a
// double-precision reference. No planet-sized coordinate is ever formed here: each patch's
// reference point O (near the camera's nadir) comes from the CPU as O − camera, and every
// difference below is built from small quantities. A record's placement holds that frame
// (runtime/draw PatchInstance.cpp, from globe::makePatchSurfaceFrame):
//   placement0  dα/du, u0, v0, α0
//   placement1  β0, tan α0, tan β0, 1/|q0|
//   placement2  d0 (xyz), √(1 − e²·d0z²)
//   placement3  O − camera (xyz, metres), N0 = a / √g0
//   placement4  metres per tile sample along s and t near O (xy)
// and layerLevel.z its cube face. Also here: the bound on how many pixels a metre of error
// covers over a set of blocks (the sphere around them) and their frustum test.
#ifndef SURFACE_GLOBE_GLSL
#define SURFACE_GLOBE_GLSL

#include "terrain_heights.glsl"
#include "terrain_patches.glsl"

// The globe's coarse stage splits at the whole ε (LodOptions::defaultCoarseShare): where
// Err(P) alone already shows more than ε, the factors hold only λ(d) to ε.
const bool kCoarseStageTakesWholeEpsilon = true;

const float kWgs84A = 6378137.0;
const float kWgs84E2 = 0.00669437999014;
// The faces' axes (io/globe CubeSphere.cpp; docs/pyramid-format.md, "Globe pyramids").
const vec3 kFaceNormal[6] = vec3[](vec3(1, 0, 0), vec3(0, 1, 0), vec3(-1, 0, 0), vec3(0, -1, 0),
                                   vec3(0, 0, 1), vec3(0, 0, -1));
const vec3 kFaceRight[6] = vec3[](vec3(0, 1, 0), vec3(-1, 0, 0), vec3(0, -1, 0), vec3(1, 0, 0),
                                  vec3(0, 1, 0), vec3(0, 1, 0));
const vec3 kFaceDown[6] = vec3[](vec3(0, 0, -1), vec3(0, 0, -1), vec3(0, 0, -1), vec3(0, 0, -1),
                                 vec3(1, 0, 0), vec3(-1, 0, 0));

// sin(x) with a small relative error for small x: GPUs' sin() has an absolute error near
// 2^-21, which would be all of sin(Δα) for the Δα of vertices near the camera.
float globeSin(float x) {
    if (abs(x) < 0.25) {
        float x2 = x * x;
        return x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0)));
    }
    return sin(x);
}

// layerLevel.w of a native tile (docs/globe.md, "Native leaves"): a tile of a source's own
// longitude/latitude grid, placed by io/globe NativeOffset.h (its GLSL twin is below); 0 for
// a face patch.
const int kNativeTile = 1;

bool isNativeTile(PatchInstance p) { return p.layerLevel.w == kNativeTile; }

// S(d) − S(d0) + (O − camera) + h·d for the direction d = d0 + Δd (SurfaceOffset.h):
// N·M·Δd + (N − N0)·M·d0, every difference formed from small quantities.
vec3 globeSurfaceOffsetM(PatchInstance p, vec3 deltaDirection, vec3 direction, float h) {
    vec3 direction0 = p.placement2.xyz;
    float sqrtG0 = p.placement2.w;
    precise float deltaG = -kWgs84E2 * deltaDirection.z * (direction.z + direction0.z);
    precise float sqrtG = sqrt(sqrtG0 * sqrtG0 + deltaG);
    precise float primeVertical = kWgs84A / sqrtG;
    precise float deltaPrimeVertical = -kWgs84A * deltaG / (sqrtG * sqrtG0 * (sqrtG + sqrtG0));
    vec3 m = vec3(1.0, 1.0, 1.0 - kWgs84E2);
    precise vec3 deltaSurface =
        primeVertical * (m * deltaDirection) + deltaPrimeVertical * (m * direction0);
    precise vec3 position = p.placement3.xyz + deltaSurface + h * direction;
    return position;
}

// atan(x) with a small relative error for small x, as globeSin.
float globeAtan(float x) {
    if (abs(x) < 0.1) {
        float x2 = x * x;
        return x * (1.0 - x2 * (1.0 / 3.0 - x2 * (1.0 / 5.0 - x2 / 7.0)));
    }
    return atan(x);
}

// Δd = d − d0 of a native tile's point at patch coordinates `uv` (io/globe NativeOffset.h,
// whose fields these are): placement0 (∂λ/∂u, u0, v0, λ0), placement1.xy (φ0, ∂φ/∂v); the rest
// as a face patch's. Longitude and latitude as reference + difference, and the direction's
// difference from sin(a0 + Δ/2)·sin(Δ/2), never as the difference of two cosines.
vec3 nativeDeltaDirection(PatchInstance p, vec2 uv) {
    // A window's coordinates on its tile (runtime/draw nativeTileInstance): texelMap's offset in
    // tile samples, placement4.w 1 / quads; exact in float, powers of two. A whole tile's are
    // its own.
    precise vec2 tileUv = p.texelMap.xy * p.placement4.w + uv * p.texelMap.z;
    precise float deltaLon = p.placement0.x * (tileUv.x - p.placement0.y);
    precise float deltaLat = p.placement1.y * (tileUv.y - p.placement0.z);
    float lon0 = p.placement0.w, lat0 = p.placement1.x;
    precise float halfLon = globeSin(0.5 * deltaLon);
    precise float halfLat = globeSin(0.5 * deltaLat);
    precise float deltaCosLon = -2.0 * sin(lon0 + 0.5 * deltaLon) * halfLon;
    precise float deltaSinLon = 2.0 * cos(lon0 + 0.5 * deltaLon) * halfLon;
    precise float deltaCosLat = -2.0 * sin(lat0 + 0.5 * deltaLat) * halfLat;
    precise float deltaSinLat = 2.0 * cos(lat0 + 0.5 * deltaLat) * halfLat;
    float cosLat = cos(lat0 + deltaLat);
    precise vec3 deltaDirection = vec3(cosLat * deltaCosLon + cos(lon0) * deltaCosLat,
                                       cosLat * deltaSinLon + sin(lon0) * deltaCosLat, deltaSinLat);
    return deltaDirection;
}

// A native tile's point at tile coordinates `uv`.
vec3 nativePositionM(PatchInstance p, vec2 uv, float h, out vec3 direction) {
    precise vec3 deltaDirection = nativeDeltaDirection(p, uv);
    direction = p.placement2.xyz + deltaDirection;
    return globeSurfaceOffsetM(p, deltaDirection, direction, h);
}

// A native tile's point at tile coordinates `uv` on the face patch whose imagery it drapes
// (io/globe NativeOffset.h, nativeImageryCoordinates, which derives it): layerLevel.z that
// patch's face, placement1.zw its coordinates of d0, placement4.z du/dα. From Δd, never from
// two planet-sized numbers: the imagery's texels stay put under the vertices.
vec2 nativeImageryUv(PatchInstance p, vec2 uv) {
    precise vec3 deltaDirection = nativeDeltaDirection(p, uv);
    int face = p.layerLevel.z;
    vec3 normal = kFaceNormal[face], right = kFaceRight[face], down = kFaceDown[face];
    vec3 direction0 = p.placement2.xyz;
    float along0 = dot(direction0, normal);
    precise float along = along0 + dot(deltaDirection, normal);
    vec2 across0 = vec2(dot(direction0, right), dot(direction0, down));
    vec2 cube0 = across0 / along0;
    precise vec2 deltaCube = (vec2(dot(deltaDirection, right), dot(deltaDirection, down)) * along0 -
                              across0 * dot(deltaDirection, normal)) /
                             (along * along0);
    precise vec2 ratio = deltaCube / (1.0 + (cube0 + deltaCube) * cube0);
    precise vec2 imageryUv =
        p.placement1.zw + vec2(globeAtan(ratio.x), globeAtan(ratio.y)) * p.placement4.z;
    return imageryUv;
}

// Camera-relative position of the patch point at patch coordinates `uv` ([0, 1]², a sample s
// at s / (N − 1)) at height h, and its ellipsoid normal `direction`.
vec3 globePositionM(PatchInstance p, vec2 uv, float h, out vec3 direction) {
    if (isNativeTile(p)) return nativePositionM(p, uv, h, direction);
    int face = p.layerLevel.z;
    vec3 faceNormal = kFaceNormal[face], right = kFaceRight[face], down = kFaceDown[face];
    // Cube coordinates as reference + difference: tan α − tan α0 = sin(Δα) / (cos α cos α0).
    precise vec2 deltaAngle = p.placement0.x * (uv - p.placement0.yz);
    vec2 angle0 = vec2(p.placement0.w, p.placement1.x);
    precise vec2 angle = angle0 + deltaAngle;
    precise vec2 deltaCube =
        vec2(globeSin(deltaAngle.x), globeSin(deltaAngle.y)) / (cos(angle) * cos(angle0));
    vec2 cube0 = p.placement1.yz;
    precise vec2 cube = cube0 + deltaCube;
    // d = q / |q| as d0 + Δd.
    precise vec3 deltaQ = deltaCube.x * right + deltaCube.y * down;
    vec3 q0 = faceNormal + cube0.x * right + cube0.y * down;
    precise float inverseLength = inversesqrt(1.0 + dot(cube, cube));
    float inverseLength0 = p.placement1.w;
    precise float deltaLengthSquared = dot(deltaCube, cube + cube0);
    precise float deltaInverseLength = -deltaLengthSquared * inverseLength * inverseLength0 /
                                       (1.0 / inverseLength + 1.0 / inverseLength0);
    precise vec3 deltaDirection = deltaQ * inverseLength + q0 * deltaInverseLength;
    direction = p.placement2.xyz + deltaDirection;
    return globeSurfaceOffsetM(p, deltaDirection, direction, h);
}

// The ellipsoid normal `up` tilted by `slope`, metres of height per metre east (along s) and
// south (along t).
vec3 globeTiltedNormal(PatchInstance p, vec2 slope, vec3 up) {
    if (isNativeTile(p)) {
        // A native tile's s runs east and t south: the parallel and the meridian.
        vec3 east = normalize(vec3(-up.y, up.x, 0.0));
        vec3 south = cross(east, up);
        return normalize(up - slope.x * east - slope.y * south);
    }
    int face = p.layerLevel.z;
    vec3 east = normalize(kFaceRight[face] - dot(kFaceRight[face], up) * up);
    vec3 south = normalize(kFaceDown[face] - dot(kFaceDown[face], up) * up);
    return normalize(up - slope.x * east - slope.y * south);
}

// The shading normal at tile sample `texel`: the ellipsoid normal `direction` tilted by the
// height differences across it over the patch's sample spacing (metres along s and t).
vec3 globeSampleShadingNormal(PatchInstance p, vec2 texel, float mode, vec3 direction) {
    int layer = p.layerLevel.x;
    float dx = tileHeight(texel + vec2(1, 0), mode, layer) - tileHeight(texel - vec2(1, 0), mode, layer);
    float dy = tileHeight(texel + vec2(0, 1), mode, layer) - tileHeight(texel - vec2(0, 1), mode, layer);
    return globeTiltedNormal(p, vec2(dx / (2.0 * p.placement4.x), dy / (2.0 * p.placement4.y)),
                             direction);
}

vec3 globeShadingNormal(PatchInstance p, vec2 texel, float mode, vec3 direction) {
    if (mode != 2.0) return globeSampleShadingNormal(p, texel, mode, direction);
    // A native window shades as its tile drawn whole does (terrain.frag, fragmentNormal): the
    // tile's sample normals blended on the source's triangle under the point, so a window and
    // its neighbours of other depths shade alike along their boundaries. The last cell's base
    // (texel quads, placement4.w being 1 / quads) keeps its corners' differences on the apron.
    vec2 base = min(floor(texel), vec2(1.0 / p.placement4.w));
    vec2 f = texel - base;
    vec3 a = globeSampleShadingNormal(p, base, 0.0, direction);
    vec3 d = globeSampleShadingNormal(p, base + vec2(1, 1), 0.0, direction);
    if (f.x >= f.y) {
        vec3 b = globeSampleShadingNormal(p, base + vec2(1, 0), 0.0, direction);
        return normalize(a + (b - a) * f.x + (d - b) * f.y);
    }
    vec3 c = globeSampleShadingNormal(p, base + vec2(0, 1), 0.0, direction);
    return normalize(a + (d - c) * f.x + (c - a) * f.y);
}

// A vertex: patch sample `s` at height h, lowered by `dropM` (a skirt's) down the ellipsoid
// normal `up`.
vec3 surfacePositionM(PatchInstance patch_, vec2 s, float h, float dropM, out vec3 up) {
    // `precise`: the division stays a division, as inside globePositionM's own expressions.
    precise vec2 uv = s / float(u_frame.tessellation.z);
    precise vec3 position = globePositionM(patch_, uv, h, up);
    position = position - dropM * up;
    return position;
}

// Where the imagery is looked up for patch sample `s` (terrain_imagery.glsl): the patch's own
// (u, v) on a face patch; on a native tile, its (u, v) on the face patch it drapes.
vec2 surfaceImageryUv(PatchInstance patch_, vec2 s) {
    precise vec2 uv = s / float(u_frame.tessellation.z);
    if (isNativeTile(patch_)) return nativeImageryUv(patch_, uv);
    return uv;
}

// Whether a native tile owns the ground at `imageryUv`, its (u, v) on the face patch it drapes
// (runtime/surface NativeOwnership.h; nativeTileOwns is the CPU twin): the bit of the cell
// there in nativeCells. It reaches past the face patches it stands for over others that draw
// themselves; drawn both, the two surfaces' pixels would interleave. Everything else, and a
// native tile whose cells are 0, owns all it covers.
bool surfaceOwnsGround(PatchInstance patch_, vec2 imageryUv) {
    ivec4 cells = patch_.nativeCells;
    if (!isNativeTile(patch_) || (cells.x | cells.y) == 0) return true;
    ivec2 cell = ivec2(floor(imageryUv)) - cells.zw;
    if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, ivec2(8)))) return false;
    int bit = 8 * cell.y + cell.x;
    return ((bit < 32 ? cells.x : cells.y) >> (bit & 31) & 1) != 0;
}

// The shading normal of slopes `slope` (metres of height per patch sample, along s and t):
// the ellipsoid normal `up` tilted as globeShadingNormal tilts it. placement4 is metres per
// tile sample; a virtual patch's sample spans texelMap.z of its ancestor's.
vec3 surfaceNormalFromSlopes(PatchInstance p, vec2 slope, vec3 up) {
    vec2 metresPerSample = p.placement4.xy * p.texelMap.z;
    return globeTiltedNormal(p, slope / metresPerSample, up);
}

vec3 surfaceShadingNormal(PatchInstance patch_, vec2 texel, float mode, vec3 up) {
    return globeShadingNormal(patch_, texel, mode, up);
}

// The globe has no edge to clip (u_frame.demExtent is ±1e30).
vec2 surfaceDemSample(PatchInstance patch_, vec2 s) { return vec2(0.0); }

// The sphere (camera-relative centre, radius) around blocks first..last of the patch between
// their heights (blocksHeightRangeM), reaching `belowM` further down.
vec4 blocksSphereM(PatchInstance patch_, ivec2 first, ivec2 last, float belowM) {
    int blockQuads = u_frame.tessellation.y;
    float patchQuads = float(u_frame.tessellation.z);
    vec3 corners[8];
    vec3 centre = vec3(0.0);
    vec3 direction;
    vec2 range = blocksHeightRangeM(patch_, first, last);
    for (int i = 0; i < 8; ++i) {
        ivec2 corner = ivec2((i & 1) != 0 ? last.x + 1 : first.x, (i & 2) != 0 ? last.y + 1 : first.y);
        float h = (i & 4) != 0 ? range.y : range.x - belowM;
        precise vec2 uv = vec2(corner * blockQuads) / patchQuads;
        corners[i] = globePositionM(patch_, uv, h, direction);
        centre += corners[i];
    }
    centre *= 0.125;
    float radius = 0.0;
    for (int i = 0; i < 8; ++i) radius = max(radius, distance(centre, corners[i]));
    // The surface bulges past its corners by at most a chord's sagitta, diagonal² / 8ρ, ρ the
    // smallest radius of curvature (6,335 km), and float rounding by a few ulps of |centre|.
    float diagonal = distance(corners[0], corners[3]);
    radius += diagonal * diagonal / (8.0 * 6.3e6) + 1.0e-5 * length(centre) + 0.05;
    return vec4(centre, radius);
}

// Pixels a metre of error covers at most over blocks first..last, their heights widened by
// `widenM` (the surface an error's segment ends on may lie that far beyond the patch's
// samples): a block of a globe patch is curved and its "vertical" is the ellipsoid normal, so
// instead of a box it takes the sphere around the blocks. An error segment of length e
// anywhere in that sphere, at distance ≥ D from the camera, spans at most
// e · f · (1 + tan²(fovX/2) + tan²(fovY/2)) / D pixels, f the focal length in pixels
// (u_frame.pixelsPerMetre.x is f times that bracket).
float blocksPxPerM(PatchInstance patch_, ivec2 first, ivec2 last, float widenM) {
    vec4 sphere = blocksSphereM(patch_, first, last, widenM);
    float distanceM = max(length(sphere.xyz) - sphere.w - widenM, u_frame.screen.w);
    return u_frame.pixelsPerMetre.x / distanceM;
}

// Whether blocks first..last of the patch, reaching `dropM` further down, lie outside the
// frustum: their sphere wholly outside one plane.
bool blocksOutsideFrustum(PatchInstance patch_, ivec2 first, ivec2 last, float dropM) {
    vec4 sphere = blocksSphereM(patch_, first, last, dropM);
    for (int i = 0; i < 5; ++i) {
        vec4 plane = u_frame.frustumPlanes[i];
        if (dot(plane.xyz, sphere.xyz) + plane.w < -sphere.w) return true;
    }
    return false;
}

// The globe has no edge: no block lies beyond it, and every skirt has a neighbour.
bool blockBeyondExtent(PatchInstance patch_, ivec2 block) { return false; }
bool skirtAlongSurfaceEdge(PatchInstance patch_, ivec2 block, int edge) { return false; }

#endif  // SURFACE_GLOBE_GLSL
