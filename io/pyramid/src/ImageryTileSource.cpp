#include "terrain/pyramid/ImageryTileSource.h"

#include "terrain/pyramid/ImageryTileReader.h"
#include "terrain/pyramid/PlanetImagery.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"

#include <fmt/format.h>

namespace terrain::io {

Result<std::unique_ptr<ImageryTileSource>> openImageryTiles(const std::filesystem::path& pyramidDir,
                                                            const PyramidManifest& manifest,
                                                            const ManifestImageryLayer& layer) {
    if (layer.kind == ManifestImageryLayer::kPlanetKind) {
        // Generated from the virtual planet the name describes (its seed), at the sea level
        // its manifest states.
        if (!isVirtualPlanetName(pyramidDir) || !manifest.globe)
            return Error{
                fmt::format("{}: imagery layer \"{}\" (planet): only the virtual "
                            "planet (\"{}…\") has the planet's colours",
                            pyramidDir.string(), layer.name, VirtualPlanetPyramid::kPrefix)};
        Result<VirtualPlanetPyramid> planet = VirtualPlanetPyramid::open(pyramidDir);
        if (!planet)
            return Error{fmt::format("{}: imagery layer \"{}\": {}", pyramidDir.string(),
                                     layer.name, planet.error().message)};
        return std::unique_ptr<ImageryTileSource>(std::make_unique<PlanetImagery>(
            planet.value().planet(), manifest.globe->seaLevelM, layer.finestLevel, layer.name));
    }
    if (layer.kind == ManifestImageryLayer::kStoredKind) {
        Result<std::unique_ptr<ImageryTileReader>> reader = ImageryTileReader::open(
            pyramidDir / layer.folder, layer.coarsestLevel, layer.finestLevel);
        if (!reader)
            return Error{
                fmt::format("imagery layer \"{}\": {}", layer.name, reader.error().message)};
        return std::unique_ptr<ImageryTileSource>(std::move(reader).value());
    }
    return Error{fmt::format("{}: imagery layer \"{}\": unknown kind \"{}\"", pyramidDir.string(),
                             layer.name, layer.kind)};
}

}  // namespace terrain::io
