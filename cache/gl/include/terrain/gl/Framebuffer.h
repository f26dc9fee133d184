// Framebuffer: an offscreen render target with an RGBA8 colour texture and a 32-bit float
// depth texture, optionally a second, single-channel float colour attachment (the reference
// renderer's world height). Headless rendering (tests, the reference renderer) draws into
// these.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Handle.h"
#include "terrain/gl/Texture.h"

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace terrain::gl {

class Framebuffer {
public:
    Framebuffer() = default;

    /// Creates the framebuffer and its two textures and checks completeness; an
    /// incomplete framebuffer is an Error naming the GL status. Render thread only.
    static Result<Framebuffer> create(int width, int height, std::string_view label = {});

    /// As create(), plus a GL_R32F colour attachment 1 for a fragment output at location 1;
    /// both colour attachments are draw buffers. Render thread only.
    static Result<Framebuffer> createWithFloatAttachment(int width, int height,
                                                         std::string_view label = {});

    /// Clears colour and depth (glClearNamedFramebuffer: no binding changes). Like any
    /// GL clear it honours the current scissor test and write masks. Render thread only.
    void clear(const std::array<float, 4>& rgba, float depth = 1.0f);

    /// Reads colour texels of a rectangle as RGBA8, rows bottom-up, tightly packed
    /// (width * height * 4 bytes). Waits for the GPU. Render thread only.
    std::vector<std::uint8_t> readColorRgba8(int x, int y, int width, int height) const;

    /// The whole colour image, as readColorRgba8(0, 0, width(), height()).
    std::vector<std::uint8_t> readColorRgba8() const;

    /// The whole depth image as float (exactly the stored 32-bit values), rows bottom-up,
    /// width * height values. Waits for the GPU. Render thread only.
    std::vector<float> readDepth() const;

    /// createWithFloatAttachment only: clears attachment 1 to `value` (no binding changes).
    void clearFloatAttachment(float value);
    /// createWithFloatAttachment only: attachment 1, rows bottom-up, width * height values.
    /// Waits for the GPU. Render thread only.
    std::vector<float> readFloatAttachment() const;
    bool hasFloatAttachment() const { return m_float.valid(); }

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }
    int width() const { return m_color.width(); }
    int height() const { return m_color.height(); }
    const Texture& depthTexture() const { return m_depth; }

private:
    static Result<Framebuffer> create(int width, int height, std::string_view label,
                                      bool floatAttachment);

    FramebufferHandle m_handle;
    Texture m_color;
    Texture m_depth;
    Texture m_float;  // optional colour attachment 1 (GL_R32F)
};

}  // namespace terrain::gl
