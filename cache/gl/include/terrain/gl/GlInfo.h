// GlInfo: what a GL context turned out to be (platform, driver strings, version, the
// limits the terrain draw depends on), for start-up checks, tools and telemetry.
#pragma once

#include <string>

namespace terrain::gl {

struct GlInfo {
    std::string platform;        ///< "egl-device", "egl-surfaceless" or "glfw"
    std::string platformDetail;  ///< e.g. "EGL 1.5 (Mesa Project), device 0 of 1 (software)"
    std::string vendor;          ///< GL_VENDOR
    std::string renderer;        ///< GL_RENDERER
    std::string version;         ///< GL_VERSION
    std::string glslVersion;     ///< GL_SHADING_LANGUAGE_VERSION
    int major = 0;
    int minor = 0;
    bool coreProfile = false;
    bool debugContext = false;
    int maxTessGenLevel = 0;        ///< GL_MAX_TESS_GEN_LEVEL
    int maxPatchVertices = 0;       ///< GL_MAX_PATCH_VERTICES
    int maxTextureSize = 0;         ///< GL_MAX_TEXTURE_SIZE
    int maxArrayTextureLayers = 0;  ///< GL_MAX_ARRAY_TEXTURE_LAYERS
    /// GL_MAX_TEXTURE_MAX_ANISOTROPY, or 1 where anisotropic filtering is unavailable
    /// (maxTextureAnisotropy()).
    float maxTextureAnisotropy = 1.0f;

    bool atLeast(int wantMajor, int wantMinor) const {
        return major > wantMajor || (major == wantMajor && minor >= wantMinor);
    }
};

/// The largest GL_TEXTURE_MAX_ANISOTROPY the current context takes: core in GL 4.6, and an
/// extension before (ARB_ or EXT_texture_filter_anisotropic, the same enums); 1 when the
/// context has neither, where setting the parameter would be a GL error. Render thread only.
float maxTextureAnisotropy();

/// Reads strings, version and limits of the current context. Render thread only.
GlInfo queryCurrentGlInfo(std::string platform, std::string platformDetail);

}  // namespace terrain::gl
