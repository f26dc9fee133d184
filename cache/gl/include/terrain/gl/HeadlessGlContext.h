// HeadlessGlContext: an OpenGL 4.5 core context with no window and no surface, through
// EGL (a GPU's EGL device, or Mesa's surfaceless platform). Rendering goes to
// framebuffer objects. Tests, the reference renderer and batch tools run on this.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/GlContext.h"

#include <memory>
#include <string_view>

namespace terrain::gl {

enum class EglPlatform {
    Automatic,    ///< TERRAIN_EGL_PLATFORM if set, else Device, then Surfaceless
    Device,       ///< EGL_EXT_platform_device: hardware devices first, then software ones
    Surfaceless,  ///< EGL_MESA_platform_surfaceless
};

/// Parses "auto", "device" or "surfaceless" (the values of TERRAIN_EGL_PLATFORM).
Result<EglPlatform> parseEglPlatform(std::string_view text);

struct HeadlessGlOptions {
    /// Automatic reads TERRAIN_EGL_PLATFORM=device|surfaceless; an explicit value here
    /// wins over the environment.
    EglPlatform platform = EglPlatform::Automatic;
    /// Ask for a debug context (more driver checks, more debug output).
    bool debugContext = true;
    /// Echo debug output to stderr.
    GlDebugEcho echoDebugMessages = GlDebugEcho::FromEnvironment;
};

class HeadlessGlContext final : public GlContext {
public:
    /// Creates the context and makes it current on the calling thread. When no platform
    /// gives OpenGL 4.5 core, the Error lists every attempt and its EGL error, and the
    /// EGL context current before (if any) is current again.
    static Result<std::unique_ptr<HeadlessGlContext>> create(const HeadlessGlOptions& options = {});

    /// Destroys the context; the context current before (if another) stays current.
    /// Render thread only.
    ~HeadlessGlContext() override;

    Status makeCurrent() override;
    const GlInfo& info() const override { return m_info; }
    GlDebugLog& debugLog() override { return m_debugLog; }
    const GlDebugLog& debugLog() const override { return m_debugLog; }

    struct Egl;  ///< EGL handles; defined in the .cpp so users need no EGL headers

private:
    HeadlessGlContext(std::unique_ptr<Egl> egl, bool echoDebugMessages);

    std::unique_ptr<Egl> m_egl;
    GlInfo m_info;
    GlDebugLog m_debugLog;
};

}  // namespace terrain::gl
