// Fills GlInfo from the current context.
#include "terrain/gl/GlInfo.h"

#include <epoxy/gl.h>

#include <utility>

namespace terrain::gl {
namespace {

std::string glString(GLenum name) {
    const GLubyte* text = glGetString(name);
    return text != nullptr ? std::string(reinterpret_cast<const char*>(text)) : std::string();
}

int glInteger(GLenum name) {
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}

}  // namespace

float maxTextureAnisotropy() {
    if (epoxy_gl_version() < 46 && !epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic") &&
        !epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic"))
        return 1.0f;
    GLfloat value = 1.0f;
    glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &value);
    return value >= 1.0f ? value : 1.0f;
}

GlInfo queryCurrentGlInfo(std::string platform, std::string platformDetail) {
    GlInfo info;
    info.platform = std::move(platform);
    info.platformDetail = std::move(platformDetail);
    info.vendor = glString(GL_VENDOR);
    info.renderer = glString(GL_RENDERER);
    info.version = glString(GL_VERSION);
    info.glslVersion = glString(GL_SHADING_LANGUAGE_VERSION);
    info.major = glInteger(GL_MAJOR_VERSION);
    info.minor = glInteger(GL_MINOR_VERSION);
    info.coreProfile = (glInteger(GL_CONTEXT_PROFILE_MASK) & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
    info.debugContext = (glInteger(GL_CONTEXT_FLAGS) & GL_CONTEXT_FLAG_DEBUG_BIT) != 0;
    // The limits below exist only from GL 4.0 on; asking an older context is a GL error.
    if (info.atLeast(4, 0)) {
        info.maxTessGenLevel = glInteger(GL_MAX_TESS_GEN_LEVEL);
        info.maxPatchVertices = glInteger(GL_MAX_PATCH_VERTICES);
    }
    info.maxTextureSize = glInteger(GL_MAX_TEXTURE_SIZE);
    info.maxArrayTextureLayers = glInteger(GL_MAX_ARRAY_TEXTURE_LAYERS);
    info.maxTextureAnisotropy = maxTextureAnisotropy();
    return info;
}

}  // namespace terrain::gl
