// PolygonModeScope: wireframe (GL_LINE) for one draw when asked, and the caller's polygon
// mode again afterwards.
#pragma once

#include <epoxy/gl.h>

namespace terrain::gl {

/// With `wireframe`, saves the polygon mode, sets GL_LINE for front and back faces and puts
/// the saved mode back when it goes; without it, touches nothing. Render thread only.
class PolygonModeScope {
public:
    explicit PolygonModeScope(bool wireframe);
    ~PolygonModeScope();
    PolygonModeScope(const PolygonModeScope&) = delete;
    PolygonModeScope& operator=(const PolygonModeScope&) = delete;

private:
    bool m_active;
    GLint m_saved[2] = {GL_FILL, GL_FILL};  // GL_POLYGON_MODE reads front and back
};

}  // namespace terrain::gl
