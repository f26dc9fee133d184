#include "NativeGrids.h"

#include "BuildBudget.h"
#include "WholeBuilds.h"
#include "terrain/pyramid/PatchErrors.h"

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
    const std::vector<float>& heights() const { return m_heights; }

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

/// The most a finest tile of a native grid (`heights`, `info`'s georeference, tiles of `quads`)
/// misses the samples of the other sources the composite shows on it: each such sample's
/// distance to the grid's cell under it, both diagonals (the tessellator picks one), maxed per
/// tile holding the cell (both where it lies on a shared tile edge). Row-major per tile.
std::vector<float> otherSourcesError(const GlobeSources& composite, std::size_t k,
                                     const std::vector<float>& heights, const DemInfo& info,
                                     int quads, std::int64_t tilesX, std::int64_t tilesY) {
    std::vector<float> error(static_cast<std::size_t>(tilesX * tilesY), 0.0f);
    const Georeference& g = info.georeference;
    const double lastX = double(info.width - 1), lastY = double(info.height - 1);
    const double middleLon = g.originX + 0.5 * double(info.width) * g.pixelSizeX;
    const double north = g.originY, south = g.originY - double(info.height) * g.pixelSizeY;
    const auto measure = [&](double latitude, double longitude, double height) {
        // The longitude nearest the grid's middle (a grid may run past ±180°).
        longitude += 360.0 * std::round((middleLon - longitude) / 360.0);
        const double x = (longitude - g.originX) / g.pixelSizeX - 0.5;
        const double y = (g.originY - latitude) / g.pixelSizeY - 0.5;
        if (!(x >= 0.0 && x <= lastX && y >= 0.0 && y <= lastY)) return;
        const auto column = std::min(static_cast<std::int64_t>(x), info.width - 2);
        const auto row = std::min(static_cast<std::int64_t>(y), info.height - 2);
        const auto at = [&](std::int64_t c, std::int64_t r) {
            return double(heights[static_cast<std::size_t>(r * info.width + c)]);
        };
        const auto [first, second] =
            cellSurfaceHeights(at(column, row), at(column + 1, row), at(column, row + 1),
                               at(column + 1, row + 1), x - double(column), y - double(row));
        const float distance =
            roundUpToFloat(std::max(std::abs(height - first), std::abs(height - second)));
        // Every tile whose samples reach the place: tile t holds samples t·q … t·q + q.
        const auto tiles = [&](double p, std::int64_t count) {
            const auto high = std::min(static_cast<std::int64_t>(std::floor(p / quads)), count - 1);
            const auto low = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(p / quads)) - 1);
            return std::pair(std::min(low, high), high);
        };
        const auto [tx0, tx1] = tiles(x, tilesX);
        const auto [ty0, ty1] = tiles(y, tilesY);
        for (std::int64_t ty = ty0; ty <= ty1; ++ty)
            for (std::int64_t tx = tx0; tx <= tx1; ++tx) {
                float& worst = error[static_cast<std::size_t>(ty * tilesX + tx)];
                worst = std::max(worst, distance);
            }
    };
    for (std::size_t j = 0; j < composite.sources().size(); ++j) {
        if (j == k) continue;
        const GlobeSources::Source& other = composite.sources()[j];
        const std::int64_t width = composite.measuredWidth(j), height = composite.measuredHeight(j);
        for (std::int64_t row = 0; row < height; ++row) {
            // A grid's rows lie at known latitudes: only those that can reach this grid.
            if (!other.own) {
                const double latitude = other.grid.latitudeOf(row);
                if (latitude > north + other.grid.pixelLatDeg() ||
                    latitude < south - other.grid.pixelLatDeg())
                    continue;
            }
            for (std::int64_t column = 0; column < width; ++column) {
                if (auto shown = composite.measuredSample(j, column, row))
                    measure(shown->latitudeDeg, shown->longitudeDeg, shown->height);
                else if (auto filled = composite.filledSample(j, column, row))
                    measure(filled->latitudeDeg, filled->longitudeDeg, filled->height);
            }
        }
    }
    return error;
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
            2 * margin);
    };
    const std::int64_t north = std::min(margin, rowsToPole(grid.northDeg()));
    const std::int64_t southLimit = rowsToPole(-grid.southDeg());
    // Grown further east and south to whole tiles, so that no tile is padded past the grid
    // with made-up samples (as far as the south pole allows).
    const auto wholeTiles = [&](std::int64_t samples) {
        return (margin - (samples - 1) % margin) % margin;
    };
    const std::int64_t east = west + wholeTiles(grid.width() + 2 * west);
    const std::int64_t south =
        std::min(southLimit, margin + wholeTiles(grid.height() + north + margin));
    const std::int64_t width = grid.width() + west + east;
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
        const std::uint64_t gridBytes = (static_cast<std::uint64_t>(grid.width()) + 3 * margin) *
                                        (static_cast<std::uint64_t>(grid.height()) + 3 * margin) *
                                        sizeof(float);
        if (Status fits = checkMemoryBudget(source.path, "its native grid (--native-leaves)",
                                            4 * gridBytes, options.memoryBudgetBytes,
                                            "give more --memory, or build without --native-leaves");
            !fits)
            return fits.error();
        planar.memoryBudgetBytes = options.memoryBudgetBytes / 2 - gridBytes;
        NativeGridReader reader = nativeGridOf(composite, k, options.patchSamples - 1);
        // Its finest tiles' Err(P) covers the other sources' samples shown on it (its own are
        // its samples): the tiles are drawn in place of face patches, against all of them.
        const int quads = options.patchSamples - 1;
        const auto tilesOf = [&](std::int64_t samples) {
            return std::max<std::int64_t>(1, (samples - 1 + quads - 1) / quads);
        };
        const std::int64_t tilesX = tilesOf(reader.info().width);
        const std::vector<float> floors =
            otherSourcesError(composite, k, reader.heights(), reader.info(), quads, tilesX,
                              tilesOf(reader.info().height));
        planar.finestErrorFloor = [&floors, tilesX](std::int64_t x, std::int64_t y) {
            return floors[static_cast<std::size_t>(y * tilesX + x)];
        };
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
