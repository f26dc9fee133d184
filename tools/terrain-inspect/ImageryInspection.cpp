#include "ImageryInspection.h"

#include "terrain/pyramid/ImageryTileReader.h"

namespace terrain::inspect {

std::vector<ImageryLayerSummary> inspectImagery(const std::filesystem::path& pyramidDir,
                                                const io::PyramidManifest& manifest, bool verify,
                                                std::vector<Problem>& problems) {
    std::vector<ImageryLayerSummary> layers;
    for (const io::ManifestImageryLayer& layer : manifest.imagery) {
        ImageryLayerSummary s{layer.name, layer.kind, layer.coarsestLevel, layer.finestLevel,
                              layer.opacity};
        if (layer.kind == io::ManifestImageryLayer::kStoredKind) {
            const std::filesystem::path folder = pyramidDir / layer.folder;
            auto reader =
                io::ImageryTileReader::open(folder, layer.coarsestLevel, layer.finestLevel);
            if (!reader) {
                problems.push_back({folder.string(), std::nullopt, reader.error().message});
            } else {
                s.tiles = reader.value()->index().presentTiles();
                s.bytes = reader.value()->index().bytes();
                if (verify) {
                    std::int64_t checked = 0;
                    if (Status v = reader.value()->verifyAll(checked); !v)
                        problems.push_back({folder.string(), std::nullopt, v.error().message});
                    s.verified = checked;
                }
            }
        }
        layers.push_back(std::move(s));
    }
    return layers;
}

}  // namespace terrain::inspect
