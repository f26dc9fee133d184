// Heights between samples, for the comparison methods whose vertices do not fall on samples
// (Valdetaro's fractional factors, Livny's triangle tiles): the bilinear interpolation of
// the four samples around a patch position, by hand from texelFetch with float weights (a
// filtering unit's few bits of sub-texel precision would give the two sides of a patch
// border different heights), and the nearest sample's central-difference normal. A vertex
// at the same DEM position in two patches gets the same height from both.
#ifndef TERRAIN_BILINEAR_GLSL
#define TERRAIN_BILINEAR_GLSL

float terrainTexel(sampler2DArray heights, ivec2 texel, int layer) {
    return texelFetch(heights, ivec3(texel, layer), 0).r;
}

// Height at patch sample position `s` (apron excluded; fractional).
float terrainBilinearHeight(sampler2DArray heights, vec2 s, int layer) {
    ivec2 cell = ivec2(floor(s));
    precise vec2 f = s - vec2(cell);
    ivec2 texel = cell + 1;  // the apron
    float h00 = terrainTexel(heights, texel, layer);
    float h10 = terrainTexel(heights, texel + ivec2(1, 0), layer);
    float h01 = terrainTexel(heights, texel + ivec2(0, 1), layer);
    float h11 = terrainTexel(heights, texel + ivec2(1, 1), layer);
    precise float h = mix(mix(h00, h10, f.x), mix(h01, h11, f.x), f.y);
    return h;
}

// The normal at the sample nearest `s`, from central differences (rows run south).
vec3 terrainNearestNormal(sampler2DArray heights, vec2 s, int layer, vec2 metresPerSample) {
    ivec2 nearest = ivec2(floor(s + 0.5)) + 1;
    float dx = terrainTexel(heights, nearest + ivec2(1, 0), layer) -
               terrainTexel(heights, nearest - ivec2(1, 0), layer);
    float dy = terrainTexel(heights, nearest - ivec2(0, 1), layer) -
               terrainTexel(heights, nearest + ivec2(0, 1), layer);
    return normalize(vec3(-dx / (2.0 * metresPerSample.x), -dy / (2.0 * metresPerSample.y), 1.0));
}

#endif  // TERRAIN_BILINEAR_GLSL
