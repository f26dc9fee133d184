// SceneTarget: the offscreen framebuffer the terrain is drawn into at the window's size —
// RGBA8 colour and a 32-bit float depth, which reversed Z needs for its precision (a
// window's default framebuffer usually has 24-bit fixed-point depth) — copied to the window
// before the overlay is drawn on top. Its depth also answers "which terrain point is under
// this pixel" for orbit pivots.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Framebuffer.h"

#include <array>
#include <optional>

namespace terrain::view {

/// Render thread only.
class SceneTarget {
public:
    /// (Re)creates the framebuffer when the size changed. Sizes must be positive.
    Status resize(int widthPx, int heightPx);

    int width() const { return m_framebuffer.width(); }
    int height() const { return m_framebuffer.height(); }

    /// Clears colour to `sky` and depth to 0 (reversed Z: far), binds it as the draw
    /// framebuffer and sets the viewport to its size.
    void beginScene(const std::array<float, 3>& sky);
    /// Binds the window's framebuffer again and copies the scene's colour into it.
    void presentToWindow();

    /// The reversed-Z depth under window pixel (xPx, yPx), origin top-left; nullopt where
    /// nothing was drawn (depth 0, the sky) or outside the framebuffer. Waits for the GPU.
    std::optional<double> depthAt(int xPx, int yPx) const;

private:
    gl::Framebuffer m_framebuffer;
};

}  // namespace terrain::view
