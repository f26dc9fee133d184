#include "terrain/pyramid/ImageryTileSource.h"

#include <fmt/format.h>

namespace terrain::io {

Result<std::unique_ptr<ImageryTileSource>> openImageryTiles(const std::filesystem::path& pyramidDir,
                                                            const PyramidManifest& manifest,
                                                            const ManifestImageryLayer& layer) {
    (void)manifest;
    return Error{fmt::format("{}: imagery layer \"{}\" ({}): not readable yet",
                             pyramidDir.string(), layer.name, layer.kind)};
}

}  // namespace terrain::io
