#include "NativeGrids.h"

#include "BuildBudget.h"
#include "WholeBuilds.h"
#include "terrain/build/PyramidShards.h"
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

/// A source's grid grown by the margin (NativeGrids.h): the samples added on each side.
struct NativeGridShape {
    std::int64_t west = 0, east = 0, north = 0, south = 0;
    std::int64_t width = 0, height = 0;
};

NativeGridShape nativeGridShape(const GeographicGrid& grid, std::int64_t margin) {
    NativeGridShape shape;
    // Grown only where the grid has an edge: not round a grid that wraps the longitudes, and
    // no further than the poles (no row centre beyond ±90°).
    shape.west = grid.wrapsLongitude() ? 0 : margin;
    const auto rowsToPole = [&](double edgeDeg) {
        return std::clamp<std::int64_t>(
            static_cast<std::int64_t>(std::floor((90.0 - edgeDeg) / grid.pixelLatDeg() + 1e-9)), 0,
            2 * margin);
    };
    shape.north = std::min(margin, rowsToPole(grid.northDeg()));
    const std::int64_t southLimit = rowsToPole(-grid.southDeg());
    // Grown further east and south to whole tiles, so that no tile is padded past the grid
    // with made-up samples (as far as the south pole allows).
    const auto wholeTiles = [&](std::int64_t samples) {
        return (margin - (samples - 1) % margin) % margin;
    };
    shape.east = shape.west + wholeTiles(grid.width() + 2 * shape.west);
    shape.south = std::min(southLimit, margin + wholeTiles(grid.height() + shape.north + margin));
    shape.width = grid.width() + shape.west + shape.east;
    shape.height = grid.height() + shape.north + shape.south;
    return shape;
}

DemInfo nativeGridInfo(const GeographicGrid& grid, const NativeGridShape& shape,
                       const std::string& sourcePath) {
    DemInfo info;
    info.path = fmt::format("{} (native grid)", sourcePath);
    info.readerName = "native";
    info.inputs = {sourcePath};
    info.width = shape.width;
    info.height = shape.height;
    info.sampleType = "float32";
    info.hasGeoreference = true;
    info.georeference.crsKind = CrsKind::Geographic;
    info.georeference.epsg = Georeference::kWgs84Geographic;
    info.georeference.originX =
        grid.westDeg() - static_cast<double>(shape.west) * grid.pixelLonDeg();
    info.georeference.originY =
        grid.northDeg() + static_cast<double>(shape.north) * grid.pixelLatDeg();
    info.georeference.pixelSizeX = grid.pixelLonDeg();
    info.georeference.pixelSizeY = grid.pixelLatDeg();
    return info;
}

/// The composite at every sample of source `k`'s grid grown by the margin.
NativeGridReader nativeGridOf(const GlobeSources& composite, std::size_t k, std::int64_t margin) {
    const GlobeSources::Source& source = composite.sources()[k];
    const GeographicGrid& grid = source.grid;
    const NativeGridShape shape = nativeGridShape(grid, margin);
    const std::int64_t west = shape.west, north = shape.north;
    const std::int64_t width = shape.width, height = shape.height;

    std::vector<float> heights(static_cast<std::size_t>(width * height));
    for (std::int64_t row = 0; row < height; ++row) {
        const std::int64_t sourceRow = row - north;
        const double latitude = grid.latitudeAt(static_cast<double>(sourceRow));
        for (std::int64_t col = 0; col < width; ++col) {
            const std::int64_t sourceCol = col - west;
            const double longitude =
                wrapLongitude(grid.longitudeAt(static_cast<double>(sourceCol)));
            // A grid round the globe grown east to whole tiles starts again at its first
            // column: those are its own samples too.
            const std::int64_t column =
                grid.wrapsLongitude() ? sourceCol % grid.wrapColumns() : sourceCol;
            std::optional<double> value;
            if (sourceRow >= 0 && sourceRow < grid.height() && column >= 0 &&
                column < grid.width()) {
                // Where the composite shows this source: its own sample, or its fill.
                if (auto own = composite.measuredSample(k, column, sourceRow))
                    value = own->height;
                else if (auto filled = composite.filledSample(k, column, sourceRow))
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
    return NativeGridReader(nativeGridInfo(grid, shape, source.path), std::move(heights));
}

/// One source's native grid read window by window from the source itself, for a region
/// build (no composite: the source alone): its filled samples, and in the margin its edge
/// samples tapered as GeographicGrid extends them (half the edge sample on the first
/// margin row or column, a quarter at a corner, the bare ellipsoid beyond). What
/// nativeGridOf holds for a composite of this one source, within a float's rounding (that
/// one reads the composite's resampling at each sample's place).
class NativeGridWindows final : public DemReader {
public:
    NativeGridWindows(DemReader& source, SourceVoids& voids, const GeographicGrid& grid,
                      std::int64_t margin)
        : m_source(source),
          m_fill(voids),
          m_grid(grid),
          m_shape(nativeGridShape(grid, margin)),
          m_info(nativeGridInfo(grid, m_shape, source.info().path)) {}

    const DemInfo& info() const override { return m_info; }

    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        assertDemWindow(m_info, x0, y0, width, rows, out);
        const std::int64_t gridWidth = m_grid.width(), gridHeight = m_grid.height();
        // The source column each column reads (clamped to the edge, or round the longitudes).
        std::vector<std::int64_t> columns(static_cast<std::size_t>(width));
        std::int64_t first = gridWidth, last = -1;
        for (std::int64_t c = 0; c < width; ++c) {
            std::int64_t column = x0 + c - m_shape.west;
            if (m_grid.wrapsLongitude()) {
                const std::int64_t turn = m_grid.wrapColumns();
                column = (column % turn + turn) % turn;
            } else {
                column = std::clamp<std::int64_t>(column, 0, gridWidth - 1);
            }
            columns[static_cast<std::size_t>(c)] = column;
            first = std::min(first, column);
            last = std::max(last, column);
        }
        const std::int64_t span = last - first + 1;
        std::vector<float> row(static_cast<std::size_t>(span));
        std::vector<std::uint8_t> valid(row.size());
        std::int64_t held = -1;  // the source row in `row`
        for (std::int64_t r = 0; r < rows; ++r) {
            const std::int64_t sourceRow = y0 + r - m_shape.north;
            const std::int64_t clampedRow = std::clamp<std::int64_t>(sourceRow, 0, gridHeight - 1);
            if (clampedRow != held) {
                if (Status read = m_source.readWindow(first, clampedRow, span, 1, row); !read)
                    return read.error();
                if (Result<std::int64_t> filled = m_fill.fill(clampedRow, first, row, valid);
                    !filled)
                    return filled.error();
                held = clampedRow;
            }
            const double y = (double(sourceRow) + 0.5) * m_grid.pixelLatDeg();
            for (std::int64_t c = 0; c < width; ++c) {
                const double x = (double(x0 + c - m_shape.west) + 0.5) * m_grid.pixelLonDeg();
                const double taper = m_grid.edgeTaper(y, x);
                const float sample =
                    row[static_cast<std::size_t>(columns[static_cast<std::size_t>(c)] - first)];
                out[static_cast<std::size_t>(r * width + c)] =
                    taper == 1.0  ? sample
                    : taper > 0.0 ? static_cast<float>(taper * sample)
                                  : 0.0f;
            }
        }
        return {};
    }

private:
    DemReader& m_source;
    RowFill m_fill;
    const GeographicGrid& m_grid;
    NativeGridShape m_shape;
    DemInfo m_info;
};

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

namespace terrain::io::detail {

Result<std::string> buildNativeGridByShards(DemReader& source, SourceVoids& voids,
                                            const GeographicGrid& grid,
                                            const fs::path& pyramidFolder,
                                            const PyramidBuildOptions& options) {
    PyramidBuildOptions planar = options;
    planar.globeNativeLeaves = false;
    planar.overwrite = true;  // a merge run again replaces the grid a failed one left
    planar.progress = nullptr;
    NativeGridWindows reader(source, voids, grid, options.patchSamples - 1);
    const std::string folder = fmt::format("{}0", ManifestGlobeSource::kNativeFolder);
    std::error_code ec;
    fs::create_directories(pyramidFolder / ManifestGlobeSource::kNativeFolder, ec);
    if (ec)
        return Error{fmt::format("{}: cannot create {}: {}", pyramidFolder.string(),
                                 ManifestGlobeSource::kNativeFolder, ec.message())};
    auto built =
        buildPyramidByShards(PyramidSurface::Plane, reader, pyramidFolder / folder, planar);
    if (!built)
        return Error{
            fmt::format("{}: its native grid: {}", source.info().path, built.error().message)};
    return folder;
}

}  // namespace terrain::io::detail
