// Ripolles et al.: the counters between steps (RipollesStrategy.cpp names the words).
//   u_phase 0, before a step: nothing written or taken yet; the family pass's dispatch and
//              the leaf pass's draw (one point a leaf).
//   u_phase 1, after it: the new tessellation becomes the current one (its draw), and the
//              free-slot stack keeps what the step did not take, the slots it freed to be
//              appended by ripolles_merge.comp.
//   u_phase 2, a reset to the input mesh (u_inputTriangles leaves, no family).
#include "Bindings.h"

layout(local_size_x = 1) in;

layout(std430, binding = TERRAIN_BINDING_RIPOLLES_COUNTERS) buffer CounterWords { uint c_words[]; };

uniform int u_phase;
uniform uint u_inputTriangles;

const uint kLeaves = 0u, kNextLeaves = 1u, kFamilyBump = 2u, kFreeSlots = 3u, kFreeTaken = 4u,
           kFreedSlots = 5u, kChanges = 6u, kMergeBase = 8u, kLeafPoints = 12u,
           kFamilyDispatch = 16u, kFreedDispatch = 20u, kDraw = 24u;

void dispatchFor(uint word, uint count) {
    c_words[word] = (count + 63u) / 64u;
    c_words[word + 1u] = 1u;
    c_words[word + 2u] = 1u;
}

void main() {
    if (u_phase == 0) {
        c_words[kNextLeaves] = 0u;
        c_words[kFreeTaken] = 0u;
        c_words[kFreedSlots] = 0u;
        c_words[kChanges] = 0u;
        c_words[kLeafPoints] = c_words[kLeaves];
        c_words[kLeafPoints + 1u] = 1u;
        c_words[kLeafPoints + 2u] = 0u;
        c_words[kLeafPoints + 3u] = 0u;
        dispatchFor(kFamilyDispatch, c_words[kFamilyBump]);
    } else if (u_phase == 1) {
        uint remaining = c_words[kFreeSlots] - min(c_words[kFreeTaken], c_words[kFreeSlots]);
        c_words[kMergeBase] = remaining;
        c_words[kFreeSlots] = remaining + c_words[kFreedSlots];
        dispatchFor(kFreedDispatch, c_words[kFreedSlots]);
        c_words[kLeaves] = c_words[kNextLeaves];
    } else {
        for (uint w = 0u; w < kDraw; ++w) c_words[w] = 0u;
        c_words[kLeaves] = u_inputTriangles;
    }
    c_words[kDraw] = 3u * c_words[kLeaves];
    c_words[kDraw + 1u] = 1u;
    c_words[kDraw + 2u] = 0u;
    c_words[kDraw + 3u] = 0u;
}
