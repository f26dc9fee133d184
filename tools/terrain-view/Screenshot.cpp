// glReadPixels of the back buffer, flipped to top-down rows, as PNG.
#include "Screenshot.h"

#include "GlImagePng.h"

#include <epoxy/gl.h>

#include <cstdint>
#include <vector>

namespace terrain::view {

Status writeWindowScreenshot(const std::filesystem::path& path, int widthPx, int heightPx) {
    const std::size_t rowBytes = static_cast<std::size_t>(widthPx) * 4;
    std::vector<std::uint8_t> bottomUp(rowBytes * static_cast<std::size_t>(heightPx));

    GLint previousRead = 0, previousAlignment = 0, previousPackBuffer = 0;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &previousRead);
    glGetIntegerv(GL_PACK_ALIGNMENT, &previousAlignment);
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &previousPackBuffer);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, widthPx, heightPx, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
    glPixelStorei(GL_PACK_ALIGNMENT, previousAlignment);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(previousPackBuffer));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(previousRead));

    return tools::writeGlRgbaPng(path, widthPx, heightPx, bottomUp);
}

}  // namespace terrain::view
