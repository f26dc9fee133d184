// readFinestLevel: each finest patch's drawn samples (the apron left out) copied to their
// place in the raster; the patches overhanging the raster's last column and row are cut.
#include "terrain/runtime/FinestLevelRaster.h"

#include "terrain/pyramid/PyramidReader.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace terrain::runtime {

Result<io::PyramidReader> openPlanarPyramid(const std::filesystem::path& pyramid,
                                            std::string_view method) {
    auto reader = io::PyramidReader::open(pyramid);
    if (!reader) return reader.error();
    if (reader.value().manifest().globe)
        return Error{pyramid.string() + ": a globe pyramid; " + std::string(method) +
                     " draws planar pyramids only"};
    return reader;
}

Result<std::vector<float>> readFinestLevel(io::PyramidReader& reader) {
    const io::PyramidLayout& layout = reader.layout();
    const auto width = static_cast<std::size_t>(layout.rasterWidth());
    const auto height = static_cast<std::size_t>(layout.rasterHeight());
    std::vector<float> raster(width * height);
    const int finest = layout.finestLevel();
    const auto tileSide = static_cast<std::size_t>(layout.tileSamples());
    const auto apron = static_cast<std::size_t>(layout.apronSamples());
    io::PatchRecord record;
    for (std::int64_t py = 0; py < layout.patchesY(finest); ++py) {
        for (std::int64_t px = 0; px < layout.patchesX(finest); ++px) {
            const io::PatchId id{finest, px, py};
            if (auto read = reader.readPatch(id, record); !read) return read.error();
            const auto x0 = static_cast<std::size_t>(layout.patchOriginX(id));
            const auto y0 = static_cast<std::size_t>(layout.patchOriginY(id));
            const std::size_t columns =
                std::min(static_cast<std::size_t>(layout.patchSamples()), width - x0);
            for (std::size_t row = 0;
                 row < static_cast<std::size_t>(layout.patchSamples()) && y0 + row < height;
                 ++row) {
                std::memcpy(raster.data() + (y0 + row) * width + x0,
                            record.heights.data() + (row + apron) * tileSide + apron,
                            columns * sizeof(float));
            }
        }
    }
    return raster;
}

}  // namespace terrain::runtime
