// Debug labels for GL objects, so debug output and GPU tools name objects, not numbers.
#pragma once

#include <epoxy/gl.h>

#include <string_view>

namespace terrain::gl {

/// Attaches a debug label (glObjectLabel) to a GL object; empty labels are ignored and
/// long ones are cut to GL_MAX_LABEL_LENGTH. Render thread only.
void setObjectLabel(GLenum identifier, GLuint name, std::string_view label);

}  // namespace terrain::gl
