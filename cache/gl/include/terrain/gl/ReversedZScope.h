// ReversedZScope: the depth state of every draw of the terrain (the LOD's and the
// reference's) while it is alive, and the caller's depth state again afterwards.
// Reversed Z (Camera::projection): clip depth in [0, 1] (glClipControl GL_ZERO_TO_ONE),
// depth = near / distance, cleared to 0, nearer is greater (GL_GREATER) — float depth then
// keeps its precision from 1 m to planetary distances.
#pragma once

#include <epoxy/gl.h>

namespace terrain::gl {

/// Saves the clip control (origin and depth mode), whether the depth test is enabled, and
/// the depth function; sets GL_LOWER_LEFT + GL_ZERO_TO_ONE, the depth test on, GL_GREATER;
/// puts the saved state back when it goes. Render thread only.
class ReversedZScope {
public:
    ReversedZScope();
    ~ReversedZScope();
    ReversedZScope(const ReversedZScope&) = delete;
    ReversedZScope& operator=(const ReversedZScope&) = delete;

private:
    GLint m_clipOrigin = GL_LOWER_LEFT;
    GLint m_clipDepthMode = GL_NEGATIVE_ONE_TO_ONE;
    GLboolean m_depthTest = GL_FALSE;
    GLint m_depthFunc = GL_LESS;
};

}  // namespace terrain::gl
