// Ripolles et al., the second pass of a tessellation step (§3.2): a geometry shader over the
// leaves (one point each) whose output points, one a triangle of the next tessellation, go to
// transform feedback — the paper's geometry shader and stream output. Each leaf:
//   - of a family that wants to change (ripolles_families.comp), or below one: once all its
//     siblings are leaves, child 0 recreates the parent (Eq. 3–6) and refines it again with
//     the pattern its edges select now, or leaves it whole ("the most suitable pattern");
//     a family below one that changes is coarsened whole; the other children emit nothing;
//     until then every child emits itself;
//   - otherwise, refined by the pattern of its own edges (Eq. 1–2), or emitted as it is.
// One step changes the tessellation by one level at most: the coherence of §3.2.
// The CPU has made the lists large enough for the step's worst case beforehand.
#include "ripolles_tessellation.glsl"

layout(points) in;
layout(points, max_vertices = 4) out;

// The next tessellation's triangle, captured as a Leaf (RipollesStrategy.cpp names them).
layout(location = 0) out vec2 o_v0;
layout(location = 1) out vec2 o_v1;
layout(location = 2) out vec2 o_v2;
layout(location = 3) flat out int o_family;
layout(location = 4) flat out int o_childType;

layout(std430, binding = TERRAIN_BINDING_RIPOLLES_LEAVES) readonly buffer Current {
    Leaf u_leaves[];
};
// The free family slots of earlier steps (a stack: this step pops from the top) and the
// ones this step frees (merged into the stack after the step).
layout(std430, binding = TERRAIN_BINDING_RIPOLLES_FREE_SLOTS) readonly buffer FreeSlots {
    int u_freeSlots[];
};
layout(std430, binding = TERRAIN_BINDING_RIPOLLES_FREED_SLOTS) writeonly buffer FreedSlots {
    int u_freedSlots[];
};

void emit(vec2 a, vec2 b, vec2 c, int family, int childType) {
    o_v0 = a;
    o_v1 = b;
    o_v2 = c;
    o_family = family;
    o_childType = childType;
    gl_Position = vec4(0.0);
    EmitVertex();
    atomicAdd(c_nextLeaves, 1u);  // the count the bookkeeping reads
}

void emitChildren(vec2 v0, vec2 v1, vec2 v2, int pattern, int family) {
    for (int c = 0; c < kChildren[pattern]; ++c) {
        ivec3 k = kPattern[pattern][c];
        emit(corner(k.x, v0, v1, v2), corner(k.y, v0, v1, v2), corner(k.z, v0, v1, v2), family, c);
    }
}

int allocateFamily() {
    uint taken = atomicAdd(c_freeTaken, 1u);
    if (taken < c_freeSlots) return u_freeSlots[c_freeSlots - 1u - taken];
    return int(atomicAdd(c_familyBump, 1u));
}

void main() {
    Leaf t = u_leaves[gl_PrimitiveIDIn];
    int f = t.family;
    if (f >= 0) {
        bool forced = false;
        for (int a = u_families[f].parentFamily; a >= 0 && !forced; a = u_families[a].parentFamily) {
            forced = u_families[a].wants != 0;
        }
        Family family = u_families[f];
        if (forced || family.wants != 0) {
            if (family.allLeavesAtStart == 0) {
                emit(t.v0, t.v1, t.v2, f, t.childType);  // a sibling is still refined: wait
                return;
            }
            if (t.childType != 0) return;  // child 0 rebuilds the family
            atomicAdd(c_changes, 1u);
            int pattern = forced ? 0 : family.wants & 7;
            if (pattern == 0) {
                emit(family.p0, family.p1, family.p2, family.parentFamily, family.parentChildType);
                if (family.parentFamily >= 0) {
                    atomicAdd(u_families[family.parentFamily].leafChildren, 1);
                }
                u_freedSlots[atomicAdd(c_freedSlots, 1u)] = f;  // ripolles_merge.comp frees it
            } else {
                u_families[f].pattern = pattern;
                u_families[f].leafChildren = kChildren[pattern];
                emitChildren(family.p0, family.p1, family.p2, pattern, f);
            }
            return;
        }
    }
    int pattern = refinementPattern(t.v0, t.v1, t.v2);
    if (pattern == 0) {
        emit(t.v0, t.v1, t.v2, f, t.childType);
        return;
    }
    atomicAdd(c_changes, 1u);
    int g = allocateFamily();
    u_families[g] = Family(t.v0, t.v1, t.v2, f, t.childType, pattern, kChildren[pattern], 0, 0);
    if (f >= 0) atomicAdd(u_families[f].leafChildren, -1);
    emitChildren(t.v0, t.v1, t.v2, pattern, g);
}
