// The scoped GL state of terrain::gl on a real context: while alive each scope sets what the
// terrain draws need, and afterwards the caller's state is back — whatever it was, not GL's
// defaults.
#include "GlTestFixture.h"
#include "terrain/gl/PolygonModeScope.h"
#include "terrain/gl/ReversedZScope.h"

#include <epoxy/gl.h>

namespace terrain::test {
namespace {

class GlStateScopeTest : public GlTest {};

struct DepthState {
    GLint clipOrigin = 0;
    GLint clipDepthMode = 0;
    GLboolean depthTest = GL_FALSE;
    GLint depthFunc = 0;
};

DepthState depthState() {
    DepthState s;
    glGetIntegerv(GL_CLIP_ORIGIN, &s.clipOrigin);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &s.clipDepthMode);
    s.depthTest = glIsEnabled(GL_DEPTH_TEST);
    glGetIntegerv(GL_DEPTH_FUNC, &s.depthFunc);
    return s;
}

void setDepthState(const DepthState& s) {
    glClipControl(static_cast<GLenum>(s.clipOrigin), static_cast<GLenum>(s.clipDepthMode));
    if (s.depthTest == GL_TRUE) {
        glEnable(GL_DEPTH_TEST);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    glDepthFunc(static_cast<GLenum>(s.depthFunc));
}

void expectDepthState(const DepthState& expected, const char* when) {
    const DepthState s = depthState();
    EXPECT_EQ(s.clipOrigin, expected.clipOrigin) << when;
    EXPECT_EQ(s.clipDepthMode, expected.clipDepthMode) << when;
    EXPECT_EQ(s.depthTest, expected.depthTest) << when;
    EXPECT_EQ(s.depthFunc, expected.depthFunc) << when;
}

TEST_F(GlStateScopeTest, ReversedZScopeSetsReversedZAndRestoresTheCallersState) {
    const DepthState reversedZ{GL_LOWER_LEFT, GL_ZERO_TO_ONE, GL_TRUE, GL_GREATER};
    // Callers whose state differs from GL's defaults in every part, or in some.
    for (const DepthState& caller :
         {DepthState{GL_UPPER_LEFT, GL_NEGATIVE_ONE_TO_ONE, GL_TRUE, GL_LEQUAL},
          DepthState{GL_LOWER_LEFT, GL_ZERO_TO_ONE, GL_FALSE, GL_ALWAYS},
          DepthState{GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE, GL_FALSE, GL_LESS}}) {
        setDepthState(caller);
        {
            const gl::ReversedZScope scope;
            expectDepthState(reversedZ, "inside the scope");
        }
        expectDepthState(caller, "after the scope");
    }
}

TEST_F(GlStateScopeTest, PolygonModeScopeDrawsLinesAndRestoresTheCallersMode) {
    GLint mode[2] = {};
    glPolygonMode(GL_FRONT_AND_BACK, GL_POINT);
    {
        const gl::PolygonModeScope wireframe(true);
        glGetIntegerv(GL_POLYGON_MODE, mode);
        EXPECT_EQ(mode[0], GL_LINE);
    }
    glGetIntegerv(GL_POLYGON_MODE, mode);
    EXPECT_EQ(mode[0], GL_POINT);
    {
        const gl::PolygonModeScope untouched(false);
        glGetIntegerv(GL_POLYGON_MODE, mode);
        EXPECT_EQ(mode[0], GL_POINT);
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
}

}  // namespace
}  // namespace terrain::test
