// A globe patch's heights from its tile (one texture-array layer, one-sample apron), shared
// by the globe draw (globe.tese) and the globe reference draw (globe_reference.vert), so both
// read a tile alike: a data patch's own samples, a virtual patch's ancestor's tile
// interpolated bilinearly between its samples; layer < 0 is the bare ellipsoid (height 0).

layout(binding = TERRAIN_BINDING_HEIGHTS) uniform sampler2DArray u_heights;

float heightAt(ivec2 texel, int layer) {
    return layer >= 0 ? texelFetch(u_heights, ivec3(texel, layer), 0).r : 0.0;
}

// The tile's height at a fractional tile sample (apron included): bilinear, as a virtual
// patch draws its ancestor's tile between its samples.
float heightBetween(vec2 texel, int layer) {
    vec2 base = floor(texel);
    vec2 f = texel - base;
    ivec2 t = ivec2(base);
    float top = mix(heightAt(t, layer), heightAt(t + ivec2(1, 0), layer), f.x);
    float bottom = mix(heightAt(t + ivec2(0, 1), layer), heightAt(t + ivec2(1, 1), layer), f.x);
    return mix(top, bottom, f.y);
}

// The shading normal at tile sample `texel`: the ellipsoid normal `direction` tilted by the
// height differences across it over the patch's sample spacing (metres along s and t).
vec3 globeShadingNormal(GlobeInstance p, vec2 texel, bool between, vec3 direction) {
    int layer = p.layerLevelFace.x;
    int face = p.layerLevelFace.z;
    vec3 east = normalize(kFaceRight[face] - dot(kFaceRight[face], direction) * direction);
    vec3 south = normalize(kFaceDown[face] - dot(kFaceDown[face], direction) * direction);
    float dx = between ? heightBetween(texel + vec2(1, 0), layer) - heightBetween(texel - vec2(1, 0), layer)
                       : heightAt(ivec2(texel) + ivec2(1, 0), layer) - heightAt(ivec2(texel) - ivec2(1, 0), layer);
    float dy = between ? heightBetween(texel + vec2(0, 1), layer) - heightBetween(texel - vec2(0, 1), layer)
                       : heightAt(ivec2(texel) + ivec2(0, 1), layer) - heightAt(ivec2(texel) - ivec2(0, 1), layer);
    return normalize(direction - dx / (2.0 * p.spacing.x) * east - dy / (2.0 * p.spacing.y) * south);
}
