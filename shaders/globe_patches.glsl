// The globe draw's shared definitions (DESIGN.md, "The globe"): the per-instance record (one
// per drawn patch, std430, matches terrain::runtime::GlobeRenderer's GlobeInstance) and the
// function that places a patch sample on the WGS84 ellipsoid relative to the camera, in
// float only: the GLSL twin of io/globe/SurfaceOffset.h, which holds the derivation and the
// test against a double-precision reference. No planet-sized coordinate is ever formed here:
// each patch's reference point O (near the camera's nadir) comes from the CPU as O − camera,
// and every difference below is built from small quantities.
#include "terrain_primitives.glsl"

struct GlobeInstance {
    vec4 frame0;      // dα/du, u0, v0, α0
    vec4 frame1;      // β0, tan α0, tan β0, 1/|q0|
    vec4 direction0;  // d0 (xyz), √(1 − e²·d0z²)
    vec4 origin;      // O − camera (xyz, metres), N0 = a / √g0
    // x: Err(P), metres; y: skirt depth, metres (SkirtDepth.h); z, w: min and max height.
    vec4 errors;
    vec4 bareBlockErrors;  // λ(1..4) of a bare patch (layer < 0); data patches read theirs
    vec4 spacing;          // x, y: metres per tile sample along s and t near O
    // A virtual patch (w = 1) draws its ancestor's tile: patch sample s lies on tile sample
    // xy + s · z. A data patch: (0, 0, 1, 0).
    vec4 texelMap;
    ivec4 layerLevelFace;  // x: texture-array layer (−1: the bare ellipsoid), y: level, z: face
};

layout(std430, binding = TERRAIN_BINDING_PATCH_INSTANCES) readonly buffer GlobeInstances {
    GlobeInstance u_globe[];
};

uniform int u_patchQuads;  // N − 1

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

// Camera-relative position of patch sample `s` (in samples, [0, N − 1]) at height h, and the
// sample's ellipsoid normal `direction`.
vec3 globePositionM(GlobeInstance p, vec2 s, float h, out vec3 direction) {
    int face = p.layerLevelFace.z;
    vec3 faceNormal = kFaceNormal[face], right = kFaceRight[face], down = kFaceDown[face];
    // Cube coordinates as reference + difference: tan α − tan α0 = sin(Δα) / (cos α cos α0).
    precise vec2 deltaAngle = p.frame0.x * (s / float(u_patchQuads) - p.frame0.yz);
    vec2 angle0 = vec2(p.frame0.w, p.frame1.x);
    precise vec2 angle = angle0 + deltaAngle;
    precise vec2 deltaCube =
        vec2(globeSin(deltaAngle.x), globeSin(deltaAngle.y)) / (cos(angle) * cos(angle0));
    vec2 cube0 = p.frame1.yz;
    precise vec2 cube = cube0 + deltaCube;
    // d = q / |q| as d0 + Δd.
    precise vec3 deltaQ = deltaCube.x * right + deltaCube.y * down;
    vec3 q0 = faceNormal + cube0.x * right + cube0.y * down;
    precise float inverseLength = inversesqrt(1.0 + dot(cube, cube));
    float inverseLength0 = p.frame1.w;
    precise float deltaLengthSquared = dot(deltaCube, cube + cube0);
    precise float deltaInverseLength = -deltaLengthSquared * inverseLength * inverseLength0 /
                                       (1.0 / inverseLength + 1.0 / inverseLength0);
    precise vec3 deltaDirection = deltaQ * inverseLength + q0 * deltaInverseLength;
    vec3 direction0 = p.direction0.xyz;
    direction = direction0 + deltaDirection;
    // S(d) − S(d0) = N·M·Δd + (N − N0)·M·d0, M = diag(1, 1, 1 − e²).
    float sqrtG0 = p.direction0.w;
    precise float deltaG = -kWgs84E2 * deltaDirection.z * (direction.z + direction0.z);
    precise float sqrtG = sqrt(sqrtG0 * sqrtG0 + deltaG);
    precise float primeVertical = kWgs84A / sqrtG;
    precise float deltaPrimeVertical = -kWgs84A * deltaG / (sqrtG * sqrtG0 * (sqrtG + sqrtG0));
    vec3 m = vec3(1.0, 1.0, 1.0 - kWgs84E2);
    precise vec3 deltaSurface =
        primeVertical * (m * deltaDirection) + deltaPrimeVertical * (m * direction0);
    precise vec3 position = p.origin.xyz + deltaSurface + h * direction;
    return position;
}
