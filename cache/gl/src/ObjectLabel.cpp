// glObjectLabel with the length limit applied, so a long label never raises a GL error.
#include "terrain/gl/ObjectLabel.h"

#include <algorithm>

namespace terrain::gl {

void setObjectLabel(GLenum identifier, GLuint name, std::string_view label) {
    if (label.empty() || name == 0) {
        return;
    }
    GLint maxLength = 0;
    glGetIntegerv(GL_MAX_LABEL_LENGTH, &maxLength);
    // GL_MAX_LABEL_LENGTH counts the terminating null; a longer label is GL_INVALID_VALUE.
    const auto length =
        std::min<std::size_t>(label.size(), static_cast<std::size_t>(std::max(maxLength, 1) - 1));
    glObjectLabel(identifier, name, static_cast<GLsizei>(length), label.data());
}

}  // namespace terrain::gl
