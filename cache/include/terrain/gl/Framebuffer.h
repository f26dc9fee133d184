// Framebuffer: an offscreen render target with an RGBA8 colour texture and a 32-bit float
// depth texture. Headless rendering (tests, the reference renderer) draws into these.
#pragma once

#include "terrain/gl/Handle.h"
#include "terrain/gl/Texture.h"
#include "terrain/io/Result.h"

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
    static io::Result<Framebuffer> create(int width, int height, std::string_view label = {});

    /// Clears colour and depth (glClearNamedFramebuffer: no binding changes). Like any
    /// GL clear it honours the current scissor test and write masks. Render thread only.
    void clear(const std::array<float, 4>& rgba, float depth = 1.0f);

    /// Reads colour texels of a rectangle as RGBA8, rows bottom-up, tightly packed
    /// (width * height * 4 bytes). Waits for the GPU. Render thread only.
    std::vector<std::uint8_t> readColorRgba8(int x, int y, int width, int height) const;

    /// The whole colour image, as readColorRgba8(0, 0, width(), height()).
    std::vector<std::uint8_t> readColorRgba8() const;

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }
    int width() const { return m_color.width(); }
    int height() const { return m_color.height(); }
    const Texture& colorTexture() const { return m_color; }
    const Texture& depthTexture() const { return m_depth; }

private:
    FramebufferHandle m_handle;
    Texture m_color;
    Texture m_depth;
};

}  // namespace terrain::gl
