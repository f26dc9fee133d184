// The terrain's shaded look, shared by draws that must look alike pixel for pixel: the
// reference renderer (reference.frag) uses it, so its image differs from the LOD draw's
// only where the geometry or the normals differ; terrain.frag uses it for every view
// (hillshade from a directional sun over a hypsometric tint, then distance fog). The sun
// is set on the C++ side by setShadingUniforms (runtime/draw/include/terrain/runtime/TerrainFrameUniforms.h).

uniform vec3 u_sunDirection;  // towards the sun, unit length, world frame
uniform vec2 u_heightRangeM;  // min, max of the DEM
uniform vec3 u_skyColor;
uniform float u_fogDensityPerM;

vec3 terrainTint(float t) {
    const vec3 low = vec3(0.34, 0.50, 0.30), mid = vec3(0.62, 0.55, 0.42), high = vec3(0.93);
    return t < 0.6 ? mix(low, mid, t / 0.6) : mix(mid, high, (t - 0.6) / 0.4);
}

// `base` lit by the sun and fogged. `normal` need not be unit length (interpolated);
// `fromCameraM` is camera-relative.
vec3 terrainShadeColor(vec3 base, vec3 normal, vec3 fromCameraM) {
    vec3 n = normalize(normal);
    float lambert = max(dot(n, u_sunDirection), 0.0);
    vec3 lit = base * (0.25 + 0.75 * lambert);
    float fog = 1.0 - exp(-u_fogDensityPerM * length(fromCameraM));
    return mix(lit, u_skyColor, fog);
}

// The shaded view: the hypsometric tint of the height, lit and fogged.
vec3 terrainShade(vec3 normal, float heightM, vec3 fromCameraM) {
    float t = clamp((heightM - u_heightRangeM.x) / max(u_heightRangeM.y - u_heightRangeM.x, 1.0),
                    0.0, 1.0);
    return terrainShadeColor(terrainTint(t), normal, fromCameraM);
}
