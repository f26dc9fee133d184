#include "GlobeSources.h"

#include "BuildBudget.h"

#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/PatchErrors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace terrain::io {

GlobeSources::GlobeSources(std::vector<Source> sources) : m_sources(std::move(sources)) {
    std::stable_sort(m_sources.begin(), m_sources.end(), [](const Source& a, const Source& b) {
        return a.grid.finestSpacingMetres() < b.grid.finestSpacingMetres();
    });
}

int finestFaceLevelOf(const GeographicGrid& grid, int quads, int oversampleLevels) {
    return finestFaceLevelOf(grid.southDeg(), grid.northDeg(), grid.westDeg(), grid.eastDeg(),
                             grid.wrapsLongitude(), grid.finestSpacingMetres(), quads,
                             oversampleLevels);
}

int finestFaceLevelOf(double southDeg, double northDeg, double westDeg, double eastDeg,
                      bool wrapsLongitude, double spacingMetres, int quads, int oversampleLevels) {
    const double centreLat = 0.5 * (northDeg + southDeg);
    const double centreLon = wrapsLongitude ? 0.0 : 0.5 * (westDeg + eastDeg);
    return std::min(
        kMaxGlobeFaceLevel,
        globeFinestLevelFor(spacingMetres, centreLat, centreLon, quads) + oversampleLevels);
}

Result<GlobeSources> GlobeSources::read(std::span<DemReader* const> readers,
                                        std::uint64_t memoryBudgetBytes, int quads,
                                        int oversampleLevels, unsigned shares) {
    std::vector<Source> sources;
    // Each source holds its share of the sources' part of the budget.
    shares *= static_cast<unsigned>(std::max<std::size_t>(1, readers.size()));
    for (DemReader* reader : readers) {
        Result<GeographicGrid> grid = GeographicGrid::read(*reader, memoryBudgetBytes, shares);
        if (!grid) return grid.error();
        const int level = finestFaceLevelOf(grid.value(), quads, oversampleLevels);
        Source source{std::move(grid).value(), level, reader->info().path, std::nullopt};
        source.noDataValue = reader->info().noDataValue;
        if (reader->info().resampledFrom) {
            Result<OwnSamples> own =
                readOwnSamples(*reader, source.grid, memoryBudgetBytes, shares);
            if (!own) return own.error();
            source.own = std::move(own).value();
        }
        sources.push_back(std::move(source));
    }
    GlobeSources composite(std::move(sources));
    if (Status filled = composite.fillVoids(); !filled) return filled.error();
    composite.fitSeamBands();
    return composite;
}

Status GlobeSources::fillVoids() {
    // Coarsest first: a source's voids are filled over the sources beneath it, already filled.
    for (std::size_t k = m_sources.size(); k-- > 0;) {
        GeographicGrid& grid = m_sources[k].grid;
        const detail::VoidFill::Beneath under = [&](std::int64_t column, std::int64_t row) {
            return beneath(k, grid.latitudeOf(row), grid.longitudeOf(column));
        };
        if (Status filled = grid.fillVoids(&under); !filled)
            return Error{m_sources[k].path + ": " + filled.error().message};
    }
    return {};
}

void GlobeSources::fitSeamBands() {
    for (std::size_t k = 0; k < m_sources.size(); ++k) {
        Source& source = m_sources[k];
        const GeographicGrid& grid = source.grid;
        if (k + 1 == m_sources.size()) {  // nothing beneath the coarsest: never blended
            source.band = SeamBand(grid.width(), grid.height(), grid.edges());
            continue;
        }
        SeamBand::Source fit;
        fit.width = grid.width();
        fit.height = grid.height();
        fit.edges = grid.edges();
        source.slopes =
            SourceSlopes(grid, kSeamSlopeShare,
                         SeamBand::kWidestShare * double(std::max(grid.width(), grid.height())));
        fit.slopeLimit = [&](SeamEdge edge, double widthPx) {
            return source.slopes.over(edge == SeamEdge::West || edge == SeamEdge::East, widthPx);
        };
        fit.eastWestMetres = [&](std::int64_t row) {
            return grid.eastWestMetres(grid.latitudeOf(row));
        };
        fit.northSouthMetres = [&](std::int64_t row) {
            return grid.northSouthMetres(grid.latitudeOf(row));
        };
        fit.step = [&](std::int64_t column, std::int64_t row) {
            return blendStepAt(k, column, row);
        };
        source.band = SeamBand::fit(fit);
    }
}

double GlobeSources::featherAt(std::size_t k, double latitudeDeg, double longitudeDeg) const {
    // The coarsest source is blended into nothing: all its own, wherever it lies (and its band
    // not looked up: a tenth of a one-source globe build).
    if (k + 1 == m_sources.size()) return 1.0;
    const Source& source = m_sources[k];
    const auto [x, y] = source.grid.pixelPosition(latitudeDeg, longitudeDeg);
    return source.band.weight(x, y);
}

std::optional<double> GlobeSources::blendStepAt(std::size_t k, std::int64_t column,
                                                std::int64_t row) const {
    const GeographicGrid& grid = m_sources[k].grid;
    const double latitude = grid.latitudeOf(row), longitude = grid.longitudeOf(column);
    for (std::size_t j = k + 1; j < m_sources.size(); ++j) {
        const GeographicGrid::Resampled under = m_sources[j].grid.at(latitude, longitude);
        if (under.valid) return double(grid.heightAt(column, row)) - double(under.height);
    }
    return std::nullopt;
}

std::optional<ManifestSeam> GlobeSources::seamOf(std::size_t k) const {
    const Source& source = m_sources[k];
    const GeographicGrid& grid = source.grid;
    const SeamBand& band = source.band;
    ManifestSeam seam;
    seam.input = source.path;
    seam.sourceSlopeP99 = source.slopes.gradient();
    seam.bandPixels = {band.narrowestPixels(), band.widestPixels()};
    seam.bandMetres = {INFINITY, 0.0};
    seam.cappedPixels = band.cappedPixels();
    bool blended = false;
    for (const SeamEdge edge : {SeamEdge::West, SeamEdge::East, SeamEdge::North, SeamEdge::South}) {
        if (!band.hasEdge(edge)) continue;
        const bool acrossColumns = edge == SeamEdge::West || edge == SeamEdge::East;
        for (std::int64_t t = 0; t < band.along(edge); ++t) {
            const double width = band.widthAt(edge, double(t));
            const double edgeLatitude = grid.latitudeOf(band.pixelAt(edge, t, 0).second);
            const double metres = width * (acrossColumns ? grid.eastWestMetres(edgeLatitude)
                                                         : grid.northSouthMetres(edgeLatitude));
            seam.bandMetres[0] = std::min(seam.bandMetres[0], metres);
            seam.bandMetres[1] = std::max(seam.bandMetres[1], metres);
            const auto depth =
                std::min(band.across(edge), static_cast<std::int64_t>(std::ceil(width)));
            for (std::int64_t d = 0; d < depth; ++d) {
                const auto [column, row] = band.pixelAt(edge, t, d);
                // Each sample once, with the band its weight follows.
                if (band.governingEdge(double(column) + 0.5, double(row) + 0.5) != edge) continue;
                const double latitude = grid.latitudeOf(row), longitude = grid.longitudeOf(column);
                const Shown shown = shownAt(latitude, longitude, 0);
                if (shown.source != static_cast<int>(k) || !shown.blended) continue;
                blended = true;
                const double step = double(grid.heightAt(column, row)) - shown.under;
                const double halfLat = 0.5 * grid.pixelLatDeg(), halfLon = 0.5 * grid.pixelLonDeg();
                const double northward = (featherAt(k, latitude + halfLat, longitude) -
                                          featherAt(k, latitude - halfLat, longitude)) /
                                         grid.northSouthMetres(latitude);
                const double eastward = (featherAt(k, latitude, longitude + halfLon) -
                                         featherAt(k, latitude, longitude - halfLon)) /
                                        grid.eastWestMetres(latitude);
                seam.largestStepM = std::max(seam.largestStepM, std::abs(step));
                const double added = std::abs(step) * std::hypot(northward, eastward);
                seam.seamSlope = std::max(seam.seamSlope, added);
                const double limit = source.slopes.over(acrossColumns, width);
                // (A flat source's limit is 0: any step is over it, by a finite figure.)
                seam.bandScaleRatio = std::max(seam.bandScaleRatio, added / std::max(limit, 1e-6));
            }
        }
    }
    if (!blended) return std::nullopt;
    return seam;
}

std::vector<ManifestSeam> GlobeSources::seams() const {
    std::vector<ManifestSeam> seams;
    for (std::size_t k = 0; k < m_sources.size(); ++k)
        if (std::optional<ManifestSeam> seam = seamOf(k)) seams.push_back(std::move(*seam));
    return seams;
}

Result<GlobeSources::OwnSamples> GlobeSources::readOwnSamples(DemReader& reader,
                                                              const GeographicGrid& grid,
                                                              std::uint64_t memoryBudgetBytes,
                                                              unsigned shares) {
    const DemInfo& dem = reader.info();
    DemReader* original = reader.originalSamples();
    if (original == nullptr)
        return Error{dem.path + ": resampled, but its own samples cannot be read"};
    OwnSamples own;
    own.width = dem.resampledFrom->width;
    own.height = dem.resampledFrom->height;
    // A height and a place each, besides the grid GeographicGrid::read counted.
    const auto bytes =
        static_cast<std::uint64_t>(double(own.width) * double(own.height) * 20.0 +
                                   double(grid.width()) * double(grid.height()) * 5.0);
    if (Status fits = detail::checkMemoryBudget(
            dem.path,
            fmt::format("holding its {} × {} samples and their resampled grid whole", own.width,
                        own.height),
            bytes * shares, memoryBudgetBytes,
            "raise --memory (a globe build holds its sources in half of it, shared among them)");
        !fits)
        return fits.error();
    const auto count = static_cast<std::size_t>(own.width * own.height);
    own.heights.resize(count);
    own.latitudes.resize(count);
    own.longitudes.resize(count);
    std::vector<double> x(static_cast<std::size_t>(own.width)), y(x.size());
    double minHeight = INFINITY, maxHeight = -INFINITY;
    for (std::int64_t row = 0; row < own.height; ++row) {
        const auto offset = static_cast<std::size_t>(row * own.width);
        std::span<float> heights(own.heights.data() + offset, x.size());
        if (Status read = original->readWindow(0, row, own.width, 1, heights); !read)
            return read.error();
        if (Status placed = reader.placeOriginalSamples(0, row, x, y); !placed)
            return placed.error();
        for (std::size_t i = 0; i < x.size(); ++i) {
            own.latitudes[offset + i] = grid.latitudeAt(y[i]);
            own.longitudes[offset + i] = grid.longitudeAt(x[i]);
            if (std::isnan(heights[i])) continue;
            ++own.validSamples;
            minHeight = std::min(minHeight, double(heights[i]));
            maxHeight = std::max(maxHeight, double(heights[i]));
        }
    }
    own.minHeight = own.validSamples > 0 ? minHeight : 0.0;
    own.maxHeight = own.validSamples > 0 ? maxHeight : 0.0;
    return own;
}

int GlobeSources::finestFaceLevel() const {
    int level = 0;
    for (const Source& s : m_sources) level = std::max(level, s.finestFaceLevel);
    return level;
}

std::optional<double> GlobeSources::beneath(std::size_t k, double latitudeDeg,
                                            double longitudeDeg) const {
    const Shown under = shownAt(latitudeDeg, longitudeDeg, 0, k + 1);
    if (under.rank > 1) return std::nullopt;  // no source beneath, or only its edge's extension
    return double(under.value.height);
}

std::optional<GlobeSources::FilledSample> GlobeSources::filledSample(std::size_t k,
                                                                     std::int64_t col,
                                                                     std::int64_t row) const {
    const GeographicGrid& grid = m_sources[k].grid;
    if (grid.validAt(col, row)) return std::nullopt;
    const double latitude = grid.latitudeOf(row), longitude = grid.longitudeOf(col);
    if (shownAt(latitude, longitude, 0).source != static_cast<int>(k)) return std::nullopt;
    return FilledSample{latitude, longitude, grid.heightAt(col, row),
                        beneath(k, latitude, longitude)};
}

GlobeSources::Shown GlobeSources::shownAt(double latitudeDeg, double longitudeDeg, int level,
                                          std::size_t first) const {
    Shown shown;
    int& rank = shown.rank;
    bool inside = false;
    for (std::size_t k = first; k < m_sources.size(); ++k) {
        const Source& source = m_sources[k];
        const GeographicGrid::Resampled value = source.grid.at(latitudeDeg, longitudeDeg);
        inside = inside || (value.inside && source.finestFaceLevel >= level);
        if (value.valid) {
            // A filled void of a finer source holds: its fill already follows this source.
            if (rank > 1) {
                shown = {static_cast<int>(k), value, featherAt(k, latitudeDeg, longitudeDeg)};
                rank = 0;
            } else if (rank <= 1 && !shown.blended && shown.feather < 1.0) {
                // The next coarser valid source under the shown one (valid or a filled void of
                // it): the feather at the shown one's edge.
                shown.value.height = static_cast<float>(
                    double(value.height) +
                    shown.feather * (double(shown.value.height) - double(value.height)));
                shown.blended = true;
                shown.under = value.height;
            }
            continue;
        }
        const int candidate = value.inside ? 1 : value.covered ? 2 : 3;
        if (candidate < rank) {
            shown = {static_cast<int>(k), value,
                     candidate == 1 ? featherAt(k, latitudeDeg, longitudeDeg) : 1.0};
            rank = candidate;
        }
    }
    shown.value.inside = inside;
    return shown;
}

GeographicGrid::Resampled GlobeSources::at(double latitudeDeg, double longitudeDeg,
                                           int level) const {
    return shownAt(latitudeDeg, longitudeDeg, level).value;
}

std::optional<std::pair<double, double>> GlobeSources::surfaceHeightsAt(double latitudeDeg,
                                                                        double longitudeDeg) const {
    const Shown shown = shownAt(latitudeDeg, longitudeDeg, 0);
    if (shown.source < 0) return std::nullopt;
    const GeographicGrid& grid = m_sources[static_cast<std::size_t>(shown.source)].grid;
    const auto cell = grid.cellAt(latitudeDeg, longitudeDeg);
    if (!cell) return std::nullopt;
    if (!shown.blended) {
        const auto [alongAD, alongBC] =
            cellSurfaceHeights(cell->a, cell->b, cell->c, cell->d, cell->u, cell->v);
        return std::pair{cell->taper * alongAD, cell->taper * alongBC};
    }
    // In a feathered border the mesh's corners are the composite's values there.
    const auto composite = [&](int dx, int dy) {
        return double(shownAt(cell->latitude[dy], cell->longitude[dx], 0).value.height);
    };
    return cellSurfaceHeights(composite(0, 0), composite(1, 0), composite(0, 1), composite(1, 1),
                              cell->u, cell->v);
}

std::int64_t GlobeSources::measuredWidth(std::size_t k) const {
    const Source& s = m_sources[k];
    return s.own ? s.own->width : s.grid.width();
}

std::int64_t GlobeSources::measuredHeight(std::size_t k) const {
    const Source& s = m_sources[k];
    return s.own ? s.own->height : s.grid.height();
}

std::optional<GlobeSources::MeasuredSample> GlobeSources::measuredSample(std::size_t k,
                                                                         std::int64_t col,
                                                                         std::int64_t row) const {
    const Source& source = m_sources[k];
    if (!source.own) {
        if (!source.grid.validAt(col, row)) return std::nullopt;
        const double latitude = source.grid.latitudeOf(row);
        const double longitude = source.grid.longitudeOf(col);
        const Shown shown = shownAt(latitude, longitude, 0);
        if (shown.source != static_cast<int>(k)) return std::nullopt;
        // The sample itself where the composite shows it unblended: resampled at its own
        // place, `at` gives it only within a rounding (6.8e-13 m for a 0 of SRTM's sea),
        // which a native grid would store (and compress far worse) in place of the sample.
        // A column repeated after 360° (ETOPO's +180°) is the first one's, as `at` reads it.
        const GeographicGrid& grid = source.grid;
        const std::int64_t column = grid.wrapsLongitude() ? col % grid.wrapColumns() : col;
        return MeasuredSample{
            latitude, longitude,
            shown.blended ? double(shown.value.height) : double(grid.heightAt(column, row))};
    }
    const auto i = static_cast<std::size_t>(row * source.own->width + col);
    const float own = source.own->heights[i];
    if (std::isnan(own)) return std::nullopt;
    const double latitude = source.own->latitudes[i], longitude = source.own->longitudes[i];
    const Shown shown = shownAt(latitude, longitude, 0);
    if (shown.source != static_cast<int>(k)) return std::nullopt;
    // The composite at the sample's place, with the sample's own value for its source's.
    const double height =
        shown.blended ? shown.under + shown.feather * (double(own) - shown.under) : double(own);
    return MeasuredSample{latitude, longitude, height};
}

}  // namespace terrain::io
