// The terrain's shaded look, shared by draws that must look alike pixel for pixel: the
// reference renderers (reference.frag) use it, so their image differs from the LOD draw's
// only where the geometry or the normals differ; terrain.frag uses it for every view
// (hillshade from a directional sun over a hypsometric tint, then distance fog; on the globe
// water below sea level). Pure functions: each stage hands in its frame's parameters
// (TerrainShading).
#ifndef TERRAIN_SHADING_GLSL
#define TERRAIN_SHADING_GLSL

struct TerrainShading {
    vec3 sunDirection;  // towards the sun, unit length, world frame
    vec2 heightRangeM;  // what the tint spans
    vec3 skyColor;      // the fog's colour
    float fogDensityPerM;
    // x: sea level, metres; y: 1 to draw what lies below it as water (the globe), 0 to tint
    // every height alike (the plane keeps its look).
    vec2 sea;
};

vec3 terrainTint(float t) {
    const vec3 low = vec3(0.34, 0.50, 0.30), mid = vec3(0.62, 0.55, 0.42), high = vec3(0.93);
    return t < 0.6 ? mix(low, mid, t / 0.6) : mix(mid, high, (t - 0.6) / 0.4);
}

// `base` lit by the sun, `ambient` of it unlit, and fogged. `normal` need not be unit length
// (interpolated); `fromCameraM` is camera-relative.
vec3 terrainLitColor(TerrainShading shading, vec3 base, vec3 normal, vec3 fromCameraM,
                     float ambient) {
    vec3 n = normalize(normal);
    float lambert = max(dot(n, shading.sunDirection), 0.0);
    vec3 lit = base * (ambient + (1.0 - ambient) * lambert);
    float fog = 1.0 - exp(-shading.fogDensityPerM * length(fromCameraM));
    return mix(lit, shading.skyColor, fog);
}

// Land: the hillshade's ambient.
vec3 terrainShadeColor(TerrainShading shading, vec3 base, vec3 normal, vec3 fromCameraM) {
    return terrainLitColor(shading, base, normal, fromCameraM, 0.25);
}

// Water by depth: shallow shelves light, the abyss dark, so coasts and shelves read from orbit.
vec3 waterTint(float depthFraction) {
    const vec3 shallow = vec3(0.36, 0.60, 0.74), deep = vec3(0.06, 0.17, 0.38);
    return mix(shallow, deep, sqrt(depthFraction));
}

// Within this of sea level a sample is sea: integer-metre DEMs (SRTM) store the sea as 0, and
// the bare ellipsoid beyond every source lies at 0.
const float kSeaToleranceM = 0.5;

// The shaded view: the hypsometric tint of the height, lit and fogged. With water on, heights
// at or below sea level are water, tinted by depth and lit softly (the sea floor's relief shows
// faintly, as under water), and the land's tint spans sea level to the highest height. Fragment
// stage only: the coast is blended over the pixel's footprint (fwidth of the height), so it
// neither aliases nor jumps a whole pixel when the LOD moves the surface by a fraction of one.
// `coastWidthM`: how much the height changes across the pixel (fwidth of a height).
vec3 terrainShade(TerrainShading shading, vec3 normal, float heightM, float coastWidthM,
                  vec3 fromCameraM) {
    vec2 range = shading.heightRangeM;
    if (shading.sea.y < 0.5) {
        float t = clamp((heightM - range.x) / max(range.y - range.x, 1.0), 0.0, 1.0);
        return terrainShadeColor(shading, terrainTint(t), normal, fromCameraM);
    }
    float seaLevel = shading.sea.x;
    float landT = clamp((heightM - seaLevel) / max(range.y - seaLevel, 1.0), 0.0, 1.0);
    vec3 land = terrainShadeColor(shading, terrainTint(landT), normal, fromCameraM);
    float depth = clamp((seaLevel - heightM) / max(seaLevel - range.x, 1.0), 0.0, 1.0);
    vec3 water = terrainLitColor(shading, waterTint(depth), normal, fromCameraM, 0.8);
    float aboveSea = heightM - (seaLevel + kSeaToleranceM);
    float landShare = clamp(0.5 + aboveSea / max(coastWidthM, 1.0e-3), 0.0, 1.0);
    return mix(water, land, landShare);
}

vec3 terrainShade(TerrainShading shading, vec3 normal, float heightM, vec3 fromCameraM) {
    return terrainShade(shading, normal, heightM, fwidth(heightM), fromCameraM);
}

#endif  // TERRAIN_SHADING_GLSL
