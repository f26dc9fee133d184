// ReversedZScope: glGet the caller's depth state, set reversed Z, put it back.
#include "terrain/gl/ReversedZScope.h"

namespace terrain::gl {

ReversedZScope::ReversedZScope() {
    glGetIntegerv(GL_CLIP_ORIGIN, &m_clipOrigin);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &m_clipDepthMode);
    m_depthTest = glIsEnabled(GL_DEPTH_TEST);
    glGetIntegerv(GL_DEPTH_FUNC, &m_depthFunc);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
}

ReversedZScope::~ReversedZScope() {
    glClipControl(static_cast<GLenum>(m_clipOrigin), static_cast<GLenum>(m_clipDepthMode));
    if (m_depthTest == GL_FALSE) glDisable(GL_DEPTH_TEST);
    glDepthFunc(static_cast<GLenum>(m_depthFunc));
}

}  // namespace terrain::gl
