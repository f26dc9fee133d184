// Screenshot: what the window shows — the terrain and the overlay — as an opaque RGBA PNG.
#pragma once

#include "terrain/base/Result.h"

#include <filesystem>

namespace terrain::view {

/// Reads the window's back buffer (call after the overlay is drawn and before the buffers
/// are swapped) and writes it to `path` through an atomic file. Errors name the file.
/// Render thread only; pack state and the read binding are put back as they were.
Status writeWindowScreenshot(const std::filesystem::path& path, int widthPx, int heightPx);

}  // namespace terrain::view
