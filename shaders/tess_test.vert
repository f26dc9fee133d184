// Tessellation test, vertex stage: passes the patch corners through unchanged.
// Stage interfaces match by location, so each stage can use the house i_/o_ names.
#include "Bindings.h"

layout(location = TERRAIN_ATTRIB_POSITION) in vec2 i_position;

layout(location = 0) out vec2 o_position;

void main() {
    o_position = i_position;
}
