// The terrain's shaded look, shared by draws that must look alike pixel for pixel: the
// reference renderers (reference.frag) use it, so their image differs from the LOD draw's
// only where the geometry or the normals differ; terrain.frag uses it for every view
// (hillshade from a directional sun over a hypsometric tint, then distance fog). Pure
// functions: each stage hands in its frame's parameters (TerrainShading).
#ifndef TERRAIN_SHADING_GLSL
#define TERRAIN_SHADING_GLSL

struct TerrainShading {
    vec3 sunDirection;  // towards the sun, unit length, world frame
    vec2 heightRangeM;  // what the tint spans
    vec3 skyColor;      // the fog's colour
    float fogDensityPerM;
};

vec3 terrainTint(float t) {
    const vec3 low = vec3(0.34, 0.50, 0.30), mid = vec3(0.62, 0.55, 0.42), high = vec3(0.93);
    return t < 0.6 ? mix(low, mid, t / 0.6) : mix(mid, high, (t - 0.6) / 0.4);
}

// `base` lit by the sun and fogged. `normal` need not be unit length (interpolated);
// `fromCameraM` is camera-relative.
vec3 terrainShadeColor(TerrainShading shading, vec3 base, vec3 normal, vec3 fromCameraM) {
    vec3 n = normalize(normal);
    float lambert = max(dot(n, shading.sunDirection), 0.0);
    vec3 lit = base * (0.25 + 0.75 * lambert);
    float fog = 1.0 - exp(-shading.fogDensityPerM * length(fromCameraM));
    return mix(lit, shading.skyColor, fog);
}

// The shaded view: the hypsometric tint of the height, lit and fogged.
vec3 terrainShade(TerrainShading shading, vec3 normal, float heightM, vec3 fromCameraM) {
    vec2 range = shading.heightRangeM;
    float t = clamp((heightM - range.x) / max(range.y - range.x, 1.0), 0.0, 1.0);
    return terrainShadeColor(shading, terrainTint(t), normal, fromCameraM);
}

#endif  // TERRAIN_SHADING_GLSL
