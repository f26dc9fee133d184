// GlImagePng: flip to top-down rows, force alpha opaque, write.
#include "GlImagePng.h"

#include "terrain/base/Assert.h"
#include "terrain/dem/RgbaImageWriter.h"

#include <cstring>
#include <vector>

namespace terrain::tools {

Status writeGlRgbaPng(const std::filesystem::path& path, int widthPx, int heightPx,
                      std::span<const std::uint8_t> bottomUpRgba) {
    const std::size_t rowBytes = static_cast<std::size_t>(widthPx) * 4;
    TERRAIN_ASSERT(bottomUpRgba.size() == rowBytes * static_cast<std::size_t>(heightPx),
                   "writeGlRgbaPng: pixel count does not match the size");
    std::vector<std::uint8_t> topDown(bottomUpRgba.size());
    for (int y = 0; y < heightPx; ++y) {
        std::memcpy(topDown.data() + static_cast<std::size_t>(y) * rowBytes,
                    bottomUpRgba.data() + static_cast<std::size_t>(heightPx - 1 - y) * rowBytes,
                    rowBytes);
    }
    // Alpha is whatever blending left there (or nothing without an alpha channel): a
    // picture of a frame is opaque.
    for (std::size_t i = 3; i < topDown.size(); i += 4) topDown[i] = 255;
    return io::writeRgba8Png(path, widthPx, heightPx, topDown);
}

Status writeFramebufferPng(const gl::Framebuffer& framebuffer, const std::filesystem::path& path) {
    return writeGlRgbaPng(path, framebuffer.width(), framebuffer.height(),
                          framebuffer.readColorRgba8());
}

}  // namespace terrain::tools
