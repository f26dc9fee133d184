// Saves, overrides and restores the pixel-store state around one pixel transfer.
#include "terrain/gl/PixelStoreScope.h"

namespace terrain::gl {

PixelStoreScope::PixelStoreScope() {
    for (std::size_t i = 0; i < kParameters.size(); ++i) {
        glGetIntegerv(kParameters[i], &m_saved[i]);
    }
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &m_savedPackBuffer);
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &m_savedUnpackBuffer);

    for (GLenum parameter : kParameters) {
        const bool isAlignment = parameter == GL_PACK_ALIGNMENT || parameter == GL_UNPACK_ALIGNMENT;
        glPixelStorei(parameter, isAlignment ? 1 : 0);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
}

PixelStoreScope::~PixelStoreScope() {
    for (std::size_t i = 0; i < kParameters.size(); ++i) {
        glPixelStorei(kParameters[i], m_saved[i]);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(m_savedPackBuffer));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(m_savedUnpackBuffer));
}

}  // namespace terrain::gl
