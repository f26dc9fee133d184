// FrameImages: one rendered frame read back to the CPU — colour, depth and (for the
// reference) world height — the input of the accuracy measures (ScreenSpaceError.h,
// ImageComparison.h).
#pragma once

#include "terrain/gl/Framebuffer.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace terrain::runtime {

/// Rows bottom-up (GL's lower-left origin), pixel (x, y) at index y · width + x.
struct FrameImages {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  ///< 4 bytes a pixel
    /// Reversed Z: nearPlane / view distance, 0 where nothing was drawn (the clear value).
    std::vector<float> depth;
    std::vector<float> heightM;  ///< world height; only from a float-attachment framebuffer

    std::size_t pixels() const {
        return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    }
    /// Something was drawn at pixel `i` (depth cleared to 0, reversed Z).
    bool drawn(std::size_t i) const { return depth[i] > 0.0f; }
};

/// Reads colour, depth and (when it has one) the float attachment of `framebuffer`.
/// Waits for the GPU. Render thread only.
inline FrameImages readFrameImages(const gl::Framebuffer& framebuffer) {
    FrameImages images;
    images.width = framebuffer.width();
    images.height = framebuffer.height();
    images.rgba = framebuffer.readColorRgba8();
    images.depth = framebuffer.readDepth();
    if (framebuffer.hasFloatAttachment()) images.heightM = framebuffer.readFloatAttachment();
    return images;
}

}  // namespace terrain::runtime
