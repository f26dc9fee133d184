// ImageryLayerIndex: an imagery layer folder's layer.json (docs/imagery.md): how its tiles
// were encoded and which tile files exist, level by level, with their tile and byte counts.
// A tile whose file the index does not list is absent; a listed file that is missing is an
// error. Any thread.
#pragma once

#include "terrain/base/Result.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace terrain::remote {
class RemoteFiles;
}

namespace terrain::io {

struct ImageryIndexFile {
    std::int64_t x = 0;  ///< group column (tile x / 16)
    std::int64_t y = 0;  ///< group row
    std::int64_t presentTiles = 0;
    std::int64_t bytes = 0;  ///< the file's size
    bool operator==(const ImageryIndexFile&) const = default;
};

struct ImageryIndexLevel {
    int level = 0;
    std::vector<ImageryIndexFile> files;  ///< sorted by (y, x)
    bool operator==(const ImageryIndexLevel&) const = default;
};

struct ImageryLayerIndex {
    static constexpr std::string_view kFormatName = "terrain-imagery-layer";
    static constexpr int kFormatVersion = 1;
    std::string codec{"webp"};
    bool lossless = false;
    int quality = 85;                       ///< lossy only
    std::vector<ImageryIndexLevel> levels;  ///< levels with at least one file, coarsest first

    std::int64_t presentTiles() const;
    std::int64_t bytes() const;  ///< of the tile files
    bool operator==(const ImageryLayerIndex&) const = default;
};

/// Writes `<layerDir>/layer.json` atomically.
Status writeImageryIndex(const std::filesystem::path& layerDir, const ImageryLayerIndex& index);
/// Reads and checks `<layerDir>/layer.json`; errors name the file.
Result<ImageryLayerIndex> readImageryIndex(const std::filesystem::path& layerDir);
/// The same, a layer at a URL fetched through `files` (so its counts include the index), or
/// from the folder where `files` is null.
Result<ImageryLayerIndex> readImageryIndex(const std::filesystem::path& layerDir,
                                           remote::RemoteFiles* files);

}  // namespace terrain::io
