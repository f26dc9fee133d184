// PolygonModeScope: glGet the caller's polygon mode, set GL_LINE, put it back.
#include "terrain/gl/PolygonModeScope.h"

namespace terrain::gl {

PolygonModeScope::PolygonModeScope(bool wireframe) : m_active(wireframe) {
    if (!m_active) return;
    glGetIntegerv(GL_POLYGON_MODE, m_saved);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
}

PolygonModeScope::~PolygonModeScope() {
    // A core profile has one mode for both faces: the first value is it.
    if (m_active) glPolygonMode(GL_FRONT_AND_BACK, static_cast<GLenum>(m_saved[0]));
}

}  // namespace terrain::gl
