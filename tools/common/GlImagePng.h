// GlImagePng: writes an image read back from OpenGL (rows bottom-up) as a PNG, the one
// way every program turns a rendered frame into a file.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Framebuffer.h"

#include <cstdint>
#include <filesystem>
#include <span>

namespace terrain::tools {

/// Writes RGBA8 pixels whose first row is the image's bottom (glReadPixels' order) as an
/// opaque PNG, top row first, through an atomic file. Errors name the file.
Status writeGlRgbaPng(const std::filesystem::path& path, int widthPx, int heightPx,
                      std::span<const std::uint8_t> bottomUpRgba);

/// The colour attachment of `framebuffer` as an opaque PNG. Render thread only.
Status writeFramebufferPng(const gl::Framebuffer& framebuffer, const std::filesystem::path& path);

}  // namespace terrain::tools
