// Lee & Shin 2011: writes the indirect arguments of the next pass from a counter the passes
// before it filled, so the CPU never reads a count between passes. LeeCounters is read as
// plain words here (GeometrySplittingStrategy.cpp gives the offsets).
#include "Bindings.h"

layout(local_size_x = 1) in;

layout(std430, binding = TERRAIN_BINDING_LEE_COUNTERS) buffer CounterWords { uint c_words[]; };

uniform uint u_countWord;      // the counter of the pass's input
uniform uint u_capacity;       // of that input list
uniform uint u_argumentsWord;  // where the arguments go
uniform bool u_draw;  // DrawArraysIndirectCommand (3 vertices a triangle), else a dispatch

void main() {
    uint count = min(c_words[u_countWord], u_capacity);
    if (u_draw) {
        c_words[u_argumentsWord] = 3u * count;
        c_words[u_argumentsWord + 1u] = 1u;
        c_words[u_argumentsWord + 2u] = 0u;
        c_words[u_argumentsWord + 3u] = 0u;
    } else {
        c_words[u_argumentsWord] = (count + 63u) / 64u;
        c_words[u_argumentsWord + 1u] = 1u;
        c_words[u_argumentsWord + 2u] = 1u;
    }
}
