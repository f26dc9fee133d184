#include "terrain/pyramid/NativeTiles.h"

#include <fmt/format.h>

namespace terrain::io {

Result<std::vector<NativeGridManifest>> readNativeGridManifests(
    const std::filesystem::path& pyramidDir, const PyramidManifest& manifest) {
    std::vector<NativeGridManifest> grids;
    if (!manifest.globe) return grids;
    const std::vector<ManifestGlobeSource>& sources = manifest.globe->sources;
    for (std::size_t k = 0; k < sources.size(); ++k) {
        if (sources[k].native.empty()) continue;
        if (k >= static_cast<std::size_t>(kMaxNativeGrids))
            return Error{
                fmt::format("{}: globe.sources: source {} has a native grid; at most "
                            "the first {} sources may have one",
                            pyramidDir.string(), k, kMaxNativeGrids)};
        Result<PyramidManifest> grid = readManifest(pyramidDir / sources[k].native);
        if (!grid) return grid.error();
        const PyramidLayout& tiles = grid.value().layout;
        if (grid.value().globe || tiles.patchSamples() != manifest.layout.patchSamples() ||
            tiles.blockQuads() != manifest.layout.blockQuads())
            return Error{fmt::format(
                "{}: its native grid {} is not a planar pyramid of patches of {} samples in "
                "blocks of {} quads, as the globe's: they share its GPU pool",
                pyramidDir.string(), sources[k].native, manifest.layout.patchSamples(),
                manifest.layout.blockQuads())};
        grids.push_back({static_cast<int>(k), std::move(grid).value()});
    }
    return grids;
}

}  // namespace terrain::io
