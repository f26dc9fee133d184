// PixelStoreScope: tight pixel packing for one transfer between client memory and GL,
// with the caller's pixel-store state and pixel buffer bindings put back afterwards.
#pragma once

#include <epoxy/gl.h>

#include <array>

namespace terrain::gl {

/// While alive: alignment 1, no row length / skips / image height, and no pixel pack or
/// unpack buffer bound (so pointers are client memory, not buffer offsets).
/// Render thread only.
class PixelStoreScope {
public:
    PixelStoreScope();
    ~PixelStoreScope();
    PixelStoreScope(const PixelStoreScope&) = delete;
    PixelStoreScope& operator=(const PixelStoreScope&) = delete;

private:
    static constexpr std::array<GLenum, 14> kParameters = {
        GL_PACK_ALIGNMENT,      GL_PACK_ROW_LENGTH,   GL_PACK_SKIP_ROWS,     GL_PACK_SKIP_PIXELS,
        GL_PACK_SKIP_IMAGES,    GL_PACK_IMAGE_HEIGHT, GL_PACK_SWAP_BYTES,    GL_UNPACK_ALIGNMENT,
        GL_UNPACK_ROW_LENGTH,   GL_UNPACK_SKIP_ROWS,  GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_IMAGES,
        GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SWAP_BYTES};

    std::array<GLint, kParameters.size()> m_saved{};
    GLint m_savedPackBuffer = 0;
    GLint m_savedUnpackBuffer = 0;
};

}  // namespace terrain::gl
