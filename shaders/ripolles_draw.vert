// Ripolles et al., the draw: the current tessellation's leaf triangles, their vertices'
// heights fetched from the height field (§3.2, "retrieving the height of the newly computed
// vertices from the heightmap"; every vertex is a DEM sample), placed as
// rtin.vert and reference.vert place theirs; reference.frag shades them and drops what lies
// beyond the DEM (the tessellated square covers the raster padded to 2^d).
#include "ripolles_tessellation.glsl"

layout(std430, binding = TERRAIN_BINDING_RIPOLLES_LEAVES) readonly buffer Current {
    Leaf u_leaves[];
};


layout(location = 0) out vec3 o_fromCameraM;
layout(location = 1) out vec3 o_normal;
layout(location = 2) out float o_heightM;
layout(location = 3) out vec2 o_demSample;

void main() {
    Leaf t = u_leaves[gl_VertexID / 3];
    int k = gl_VertexID % 3;
    vec2 s = k == 0 ? t.v0 : (k == 1 ? t.v1 : t.v2);
    float h = heightAt(s);
    float dx = heightAt(s + vec2(1.0, 0.0)) - heightAt(s - vec2(1.0, 0.0));
    float dy = heightAt(s - vec2(0.0, 1.0)) - heightAt(s + vec2(0.0, 1.0));  // rows run south
    o_normal = normalize(vec3(-dx / (2.0 * u_frame.planeSpacing.x), -dy / (2.0 * u_frame.planeSpacing.y), 1.0));
    o_heightM = h;
    o_demSample = s - planeAnchorSample();
    vec3 position = fromCamera(s);
    o_fromCameraM = position;
    gl_Position = u_frame.viewProjection * vec4(position, 1.0);
}
