// GlContext: an OpenGL 4.5 core context, headless (EGL) or in a window (GLFW), behind one
// interface so renderer, tools and tests do not care which one they run on.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/DriverWorkarounds.h"
#include "terrain/gl/GlDebugLog.h"
#include "terrain/gl/GlInfo.h"

namespace terrain::gl {

/// The OpenGL version every context must provide (tessellation, DSA, glGetTextureSubImage).
inline constexpr int kRequiredGlMajor = 4;
inline constexpr int kRequiredGlMinor = 5;

/// A context and its debug log. A context is created current on the calling thread, which
/// becomes its render thread; GL objects are created and destroyed there, before the
/// context itself is destroyed. A thread has one current context at a time: code that
/// switches between contexts calls makeCurrent() on the one it means.
class GlContext {
public:
    GlContext() = default;
    virtual ~GlContext() = default;
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    /// Makes this context current on the calling thread. Render thread only.
    virtual Status makeCurrent() = 0;

    /// What the context turned out to be; filled at creation.
    virtual const GlInfo& info() const = 0;

    /// GL debug output of this context.
    virtual GlDebugLog& debugLog() = 0;
    virtual const GlDebugLog& debugLog() const = 0;

    /// What applyDriverWorkarounds() did when the context was created (tools report it
    /// in their --json beside info(), so a figure names what was worked around).
    const DriverWorkaroundsApplied& driverWorkarounds() const { return m_driverWorkarounds; }

protected:
    DriverWorkaroundsApplied m_driverWorkarounds;
};

}  // namespace terrain::gl
