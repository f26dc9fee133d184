// RgbaImageWriter: saves rendered frames (8-bit RGBA) as PNG, atomically.
#pragma once

#include "terrain/base/Result.h"

#include <cstdint>
#include <filesystem>
#include <span>

namespace terrain::io {

/// Writes width × height RGBA8 pixels, rows top to bottom (flip glReadPixels output
/// first), as an 8-bit RGBA PNG through an AtomicFile. `pixels` holds width·height·4
/// bytes. Errors name path. Calling thread.
Status writeRgba8Png(const std::filesystem::path& path, std::int64_t width, std::int64_t height,
                     std::span<const std::uint8_t> pixels);

}  // namespace terrain::io
