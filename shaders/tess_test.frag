// Tessellation test, fragment stage: red = u, green = v of the tessellated domain.
#include "Bindings.h"

layout(location = 0) in vec2 i_tessCoord;

layout(location = TERRAIN_FRAG_COLOR) out vec4 o_color;

void main() {
    o_color = vec4(i_tessCoord, 0.0, 1.0);
}
