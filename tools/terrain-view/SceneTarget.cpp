// Offscreen scene framebuffer, copied to the window each frame.
#include "SceneTarget.h"

#include <epoxy/gl.h>

#include <cstddef>
#include <span>

namespace terrain::view {

Status SceneTarget::resize(int widthPx, int heightPx) {
    if (m_framebuffer.valid() && widthPx == width() && heightPx == height()) return {};
    auto created = gl::Framebuffer::create(widthPx, heightPx, "terrain-view scene");
    if (!created) return created.error();
    m_framebuffer = std::move(created).value();
    return {};
}

void SceneTarget::beginScene(const std::array<float, 3>& sky) {
    m_framebuffer.clear({sky[0], sky[1], sky[2], 1.0f}, 0.0f);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_framebuffer.id());
    glViewport(0, 0, width(), height());
}

void SceneTarget::presentToWindow() {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitNamedFramebuffer(m_framebuffer.id(), 0, 0, 0, width(), height(), 0, 0, width(), height(),
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

std::optional<double> SceneTarget::depthAt(int xPx, int yPx) const {
    if (!m_framebuffer.valid() || xPx < 0 || yPx < 0 || xPx >= width() || yPx >= height()) {
        return std::nullopt;
    }
    float depth = 0.0f;
    const gl::TextureRegion texel{.x = xPx, .y = height() - 1 - yPx, .width = 1, .height = 1};
    m_framebuffer.depthTexture().readBack(texel, GL_DEPTH_COMPONENT, GL_FLOAT,
                                          std::as_writable_bytes(std::span<float>(&depth, 1)));
    if (!(depth > 0.0f)) return std::nullopt;
    return static_cast<double>(depth);
}

}  // namespace terrain::view
