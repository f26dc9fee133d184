#include "NativeGrids.h"

#include "BuildBudget.h"
#include "WholeBuilds.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace terrain::io::detail {
namespace {

namespace fs = std::filesystem;

/// One source's native grid held in memory, read as a DEM by the planar builder: the
/// composite at the source's samples, grown by the margin (NativeGrids.h).
class NativeGridReader final : public DemReader {
public:
    NativeGridReader(DemInfo info, std::vector<float> heights)
        : m_info(std::move(info)), m_heights(std::move(heights)) {}

    const DemInfo& info() const override { return m_info; }

    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        assertDemWindow(m_info, x0, y0, width, rows, out);
        for (std::int64_t r = 0; r < rows; ++r)
            std::memcpy(out.data() + r * width, m_heights.data() + (y0 + r) * m_info.width + x0,
                        static_cast<std::size_t>(width) * sizeof(float));
        return {};
    }

private:
    DemInfo m_info;
    std::vector<float> m_heights;
};

/// Longitude in [−180, 180).
double wrapLongitude(double longitudeDeg) {
    const double wrapped = std::fmod(longitudeDeg + 180.0, 360.0);
    return (wrapped < 0.0 ? wrapped + 360.0 : wrapped) - 180.0;
}

/// The composite at every sample of source `k`'s grid grown by the margin.
NativeGridReader nativeGridOf(const GlobeSources& composite, std::size_t k, std::int64_t margin) {
    const GlobeSources::Source& source = composite.sources()[k];
    const GeographicGrid& grid = source.grid;
    // Grown only where the grid has an edge: not round a grid that wraps the longitudes, and
    // no further than the poles (no row centre beyond ±90°).
    const std::int64_t west = grid.wrapsLongitude() ? 0 : margin;
    const auto rowsToPole = [&](double edgeDeg) {
        return std::clamp<std::int64_t>(
            static_cast<std::int64_t>(std::floor((90.0 - edgeDeg) / grid.pixelLatDeg() + 1e-9)), 0,
            margin);
    };
    const std::int64_t north = rowsToPole(grid.northDeg());
    const std::int64_t south = rowsToPole(-grid.southDeg());
    const std::int64_t width = grid.width() + 2 * west;
    const std::int64_t height = grid.height() + north + south;

    std::vector<float> heights(static_cast<std::size_t>(width * height));
    for (std::int64_t row = 0; row < height; ++row) {
        const std::int64_t sourceRow = row - north;
        const double latitude = grid.latitudeAt(static_cast<double>(sourceRow));
        for (std::int64_t col = 0; col < width; ++col) {
            const std::int64_t sourceCol = col - west;
            const double longitude =
                wrapLongitude(grid.longitudeAt(static_cast<double>(sourceCol)));
            std::optional<double> value;
            if (sourceRow >= 0 && sourceRow < grid.height() && sourceCol >= 0 &&
                sourceCol < grid.width()) {
                // Where the composite shows this source: its own sample, or its fill.
                if (auto own = composite.measuredSample(k, sourceCol, sourceRow))
                    value = own->height;
                else if (auto filled = composite.filledSample(k, sourceCol, sourceRow))
                    value = filled->height;
            }
            if (!value) {
                // Under a finer source, or in the margin: the composite's surface here, on the
                // triangles its builder and its truth use (the north-west – south-east
                // diagonal); the bare ellipsoid where no source reaches.
                const auto surface = composite.surfaceHeightsAt(latitude, longitude);
                value = surface ? surface->first : 0.0;
            }
            heights[static_cast<std::size_t>(row * width + col)] = static_cast<float>(*value);
        }
    }

    DemInfo info;
    info.path = fmt::format("{} (native grid)", source.path);
    info.readerName = "native";
    info.inputs = {source.path};
    info.width = width;
    info.height = height;
    info.sampleType = "float32";
    info.hasGeoreference = true;
    info.georeference.crsKind = CrsKind::Geographic;
    info.georeference.epsg = Georeference::kWgs84Geographic;
    info.georeference.originX = grid.westDeg() - static_cast<double>(west) * grid.pixelLonDeg();
    info.georeference.originY = grid.northDeg() + static_cast<double>(north) * grid.pixelLatDeg();
    info.georeference.pixelSizeX = grid.pixelLonDeg();
    info.georeference.pixelSizeY = grid.pixelLatDeg();
    return NativeGridReader(std::move(info), std::move(heights));
}

}  // namespace

Result<std::vector<std::string>> buildNativeGrids(const GlobeSources& composite,
                                                  const fs::path& pyramidFolder,
                                                  const PyramidBuildOptions& options) {
    std::vector<std::string> folders(composite.sources().size());
    PyramidBuildOptions planar = options;
    planar.globeNativeLeaves = false;
    planar.overwrite = false;
    planar.progress = nullptr;
    for (std::size_t k = 0; k < composite.sources().size(); ++k) {
        const GlobeSources::Source& source = composite.sources()[k];
        // A projected source's own samples do not lie on the grid it was warped onto.
        if (source.own) continue;
        // The grid is held whole beside the sources (half the budget, GlobeSources::read) while
        // the planar build streams it: it may take half of the other half, the build the rest.
        const GeographicGrid& grid = source.grid;
        const auto margin = static_cast<std::uint64_t>(options.patchSamples - 1);
        const std::uint64_t gridBytes = (static_cast<std::uint64_t>(grid.width()) + 2 * margin) *
                                        (static_cast<std::uint64_t>(grid.height()) + 2 * margin) *
                                        sizeof(float);
        if (Status fits = checkMemoryBudget(source.path, "its native grid (--native-leaves)",
                                            4 * gridBytes, options.memoryBudgetBytes,
                                            "give more --memory, or build without --native-leaves");
            !fits)
            return fits.error();
        planar.memoryBudgetBytes = options.memoryBudgetBytes / 2 - gridBytes;
        NativeGridReader reader = nativeGridOf(composite, k, options.patchSamples - 1);
        const std::string folder = fmt::format("{}{}", ManifestGlobeSource::kNativeFolder, k);
        std::error_code ec;
        fs::create_directories(pyramidFolder / ManifestGlobeSource::kNativeFolder, ec);
        if (ec)
            return Error{fmt::format("{}: cannot create {}: {}", pyramidFolder.string(),
                                     ManifestGlobeSource::kNativeFolder, ec.message())};
        auto built = buildWholePlanarPyramid(reader, pyramidFolder / folder, planar);
        if (!built)
            return Error{
                fmt::format("{}: its native grid: {}", source.path, built.error().message)};
        folders[k] = folder;
    }
    return folders;
}

}  // namespace terrain::io::detail
