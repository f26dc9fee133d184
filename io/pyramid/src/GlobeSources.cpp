#include "GlobeSources.h"

#include "terrain/io/GlobePyramidBuilder.h"
#include "terrain/io/PatchErrors.h"

#include <algorithm>
#include <string>

namespace terrain::io {

GlobeSources::GlobeSources(std::vector<Source> sources) : m_sources(std::move(sources)) {
    std::stable_sort(m_sources.begin(), m_sources.end(), [](const Source& a, const Source& b) {
        return a.grid.finestSpacingMetres() < b.grid.finestSpacingMetres();
    });
}

Result<GlobeSources> GlobeSources::read(std::span<DemReader* const> readers,
                                        std::uint64_t memoryBudgetBytes, int quads) {
    std::vector<Source> sources;
    for (DemReader* reader : readers) {
        // Its bounds would hold for the resampled grid only, not the source's own samples.
        if (reader->info().resampledFrom)
            return Error{reader->info().path +
                         ": a rotated or sheared grid cannot go into a globe pyramid yet; "
                         "resample it onto a north-up grid first (gdalwarp)"};
        Result<GeographicGrid> grid = GeographicGrid::read(
            *reader, memoryBudgetBytes / std::max<std::size_t>(1, readers.size()));
        if (!grid) return grid.error();
        const GeographicGrid& g = grid.value();
        const double centreLat = 0.5 * (g.northDeg() + g.southDeg());
        const double centreLon = g.wrapsLongitude() ? 0.0 : 0.5 * (g.westDeg() + g.eastDeg());
        const int level = globeFinestLevelFor(g.finestSpacingMetres(), centreLat, centreLon, quads);
        sources.push_back({std::move(grid).value(), level, reader->info().path});
    }
    return GlobeSources(std::move(sources));
}

int GlobeSources::finestFaceLevel() const {
    int level = 0;
    for (const Source& s : m_sources) level = std::max(level, s.finestFaceLevel);
    return level;
}

GlobeSources::Shown GlobeSources::shownAt(double latitudeDeg, double longitudeDeg,
                                          int level) const {
    Shown shown;
    int rank = 3;  // of shown.value: 0 valid, 1 a filled void, 2 an extended edge pixel, 3 none
    double voidSpacing = 0.0;  // the source whose void is being filled, its spacing
    bool inside = false;
    for (std::size_t k = 0; k < m_sources.size(); ++k) {
        const Source& source = m_sources[k];
        const GeographicGrid::Resampled value = source.grid.at(latitudeDeg, longitudeDeg);
        inside = inside || (value.inside && source.finestFaceLevel >= level);
        if (value.valid) {
            // A void falls through to this source only if it is of comparable resolution.
            const bool fills = rank > 1 || (rank == 1 && source.grid.finestSpacingMetres() <=
                                                             kVoidFillRatio * voidSpacing);
            if (fills) {
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
            }
            continue;
        }
        const int candidate = value.inside ? 1 : value.covered ? 2 : 3;
        if (candidate < rank) {
            shown = {static_cast<int>(k), value,
                     candidate == 1 ? source.grid.featherAt(latitudeDeg, longitudeDeg) : 1.0};
            rank = candidate;
            if (candidate == 1) voidSpacing = source.grid.finestSpacingMetres();
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

double GlobeSources::shownHeightOfSample(std::size_t k, std::int64_t col, std::int64_t row) const {
    const GeographicGrid& grid = m_sources[k].grid;
    return shownAt(grid.latitudeOf(row), grid.longitudeOf(col), 0).value.height;
}

bool GlobeSources::wins(std::size_t k, std::int64_t col, std::int64_t row) const {
    const GeographicGrid& grid = m_sources[k].grid;
    if (!grid.validAt(col, row)) return false;
    return shownAt(grid.latitudeOf(row), grid.longitudeOf(col), 0).source == static_cast<int>(k);
}

}  // namespace terrain::io
