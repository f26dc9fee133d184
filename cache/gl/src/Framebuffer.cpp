// Offscreen framebuffer: colour RGBA8 + depth32F textures (+ an optional R32F colour
// attachment), completeness checked once.
#include "terrain/gl/Framebuffer.h"

#include "terrain/base/Assert.h"

#include <array>
#include <cstddef>
#include <span>
#include <string>

namespace terrain::gl {
namespace {

const char* framebufferStatusName(GLenum status) {
    switch (status) {
        case GL_FRAMEBUFFER_COMPLETE:
            return "GL_FRAMEBUFFER_COMPLETE";
        case GL_FRAMEBUFFER_UNDEFINED:
            return "GL_FRAMEBUFFER_UNDEFINED";
        case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
            return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
        case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
            return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
        case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER:
            return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
        case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER:
            return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
        case GL_FRAMEBUFFER_UNSUPPORTED:
            return "GL_FRAMEBUFFER_UNSUPPORTED";
        case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
            return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
        case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS:
            return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
        default:
            return "unknown framebuffer status";
    }
}

}  // namespace

Result<Framebuffer> Framebuffer::create(int width, int height, std::string_view label) {
    return create(width, height, label, false);
}

Result<Framebuffer> Framebuffer::createWithFloatAttachment(int width, int height,
                                                           std::string_view label) {
    return create(width, height, label, true);
}

Result<Framebuffer> Framebuffer::create(int width, int height, std::string_view label,
                                        bool floatAttachment) {
    const std::string name =
        label.empty() ? std::string("framebuffer") : "framebuffer '" + std::string(label) + "'";
    const std::string colorLabel = std::string(label) + " colour";
    const std::string depthLabel = std::string(label) + " depth";
    auto color = Texture::create2D({.internalFormat = GL_RGBA8, .width = width, .height = height},
                                   label.empty() ? std::string_view() : colorLabel);
    if (!color) {
        return Error{name + ": " + color.error().message};
    }
    auto depth = Texture::create2D(
        {.internalFormat = GL_DEPTH_COMPONENT32F, .width = width, .height = height},
        label.empty() ? std::string_view() : depthLabel);
    if (!depth) {
        return Error{name + ": " + depth.error().message};
    }

    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    Framebuffer framebuffer;
    framebuffer.m_handle = FramebufferHandle(id);
    framebuffer.m_color = std::move(color).value();
    framebuffer.m_depth = std::move(depth).value();
    // Exact texel values matter for readback: no filtering between texels.
    framebuffer.m_color.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    framebuffer.m_depth.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0, framebuffer.m_color.id(), 0);
    glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, framebuffer.m_depth.id(), 0);
    if (floatAttachment) {
        const std::string floatLabel = std::string(label) + " float";
        auto extra =
            Texture::create2D({.internalFormat = GL_R32F, .width = width, .height = height},
                              label.empty() ? std::string_view() : floatLabel);
        if (!extra) {
            return Error{name + ": " + extra.error().message};
        }
        framebuffer.m_float = std::move(extra).value();
        framebuffer.m_float.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
        glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT1, framebuffer.m_float.id(), 0);
        const std::array<GLenum, 2> drawBuffers{GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(id, 2, drawBuffers.data());
    } else {
        glNamedFramebufferDrawBuffer(id, GL_COLOR_ATTACHMENT0);
    }
    glNamedFramebufferReadBuffer(id, GL_COLOR_ATTACHMENT0);

    const GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        return Error{name + ": incomplete (" + framebufferStatusName(status) + ")"};
    }
    framebuffer.m_handle.setLabel(label);
    return framebuffer;
}

void Framebuffer::clear(const std::array<float, 4>& rgba, float depth) {
    TERRAIN_ASSERT(valid());
    glClearNamedFramebufferfv(id(), GL_COLOR, 0, rgba.data());
    glClearNamedFramebufferfv(id(), GL_DEPTH, 0, &depth);
}

std::vector<std::uint8_t> Framebuffer::readColorRgba8(int x, int y, int width, int height) const {
    TERRAIN_ASSERT(valid());
    const TextureRegion region{.x = x, .y = y, .width = width, .height = height};
    std::vector<std::uint8_t> pixels(Texture::imageSizeBytes(region, GL_RGBA, GL_UNSIGNED_BYTE));
    m_color.readBack(region, GL_RGBA, GL_UNSIGNED_BYTE, std::as_writable_bytes(std::span(pixels)));
    return pixels;
}

std::vector<std::uint8_t> Framebuffer::readColorRgba8() const {
    return readColorRgba8(0, 0, width(), height());
}

std::vector<float> Framebuffer::readDepth() const {
    TERRAIN_ASSERT(valid());
    const TextureRegion region = m_depth.wholeLevel(0);
    std::vector<float> depth(static_cast<std::size_t>(region.width) *
                             static_cast<std::size_t>(region.height));
    m_depth.readBack(region, GL_DEPTH_COMPONENT, GL_FLOAT,
                     std::as_writable_bytes(std::span(depth)));
    return depth;
}

void Framebuffer::clearFloatAttachment(float value) {
    TERRAIN_ASSERT(hasFloatAttachment(), "Framebuffer: no float attachment");
    const std::array<float, 4> rgba{value, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(id(), GL_COLOR, 1, rgba.data());
}

std::vector<float> Framebuffer::readFloatAttachment() const {
    TERRAIN_ASSERT(hasFloatAttachment(), "Framebuffer: no float attachment");
    const TextureRegion region = m_float.wholeLevel(0);
    std::vector<float> values(static_cast<std::size_t>(region.width) *
                              static_cast<std::size_t>(region.height));
    m_float.readBack(region, GL_RED, GL_FLOAT, std::as_writable_bytes(std::span(values)));
    return values;
}

}  // namespace terrain::gl
