#include "GlobeSources.h"

#include "BuildBudget.h"

#include "terrain/build/GlobePyramidBuilder.h"
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

int finestFaceLevelOf(const GeographicGrid& grid, int quads) {
    const double centreLat = 0.5 * (grid.northDeg() + grid.southDeg());
    const double centreLon = grid.wrapsLongitude() ? 0.0 : 0.5 * (grid.westDeg() + grid.eastDeg());
    return globeFinestLevelFor(grid.finestSpacingMetres(), centreLat, centreLon, quads);
}

Result<GlobeSources> GlobeSources::read(std::span<DemReader* const> readers,
                                        std::uint64_t memoryBudgetBytes, int quads,
                                        unsigned shares) {
    std::vector<Source> sources;
    // Each source holds its share of the sources' part of the budget.
    shares *= static_cast<unsigned>(std::max<std::size_t>(1, readers.size()));
    for (DemReader* reader : readers) {
        Result<GeographicGrid> grid = GeographicGrid::read(*reader, memoryBudgetBytes, shares);
        if (!grid) return grid.error();
        const int level = finestFaceLevelOf(grid.value(), quads);
        Source source{std::move(grid).value(), level, reader->info().path, std::nullopt};
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
                shown = {static_cast<int>(k), value,
                         source.grid.featherAt(latitudeDeg, longitudeDeg)};
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
                     candidate == 1 ? source.grid.featherAt(latitudeDeg, longitudeDeg) : 1.0};
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
    if (!shown.blended)
        return cellSurfaceHeights(cell->a, cell->b, cell->c, cell->d, cell->u, cell->v);
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
        return MeasuredSample{latitude, longitude, shown.value.height};
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
