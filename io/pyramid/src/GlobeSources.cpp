#include "GlobeSources.h"

#include "terrain/io/GlobePyramidBuilder.h"

#include <algorithm>

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

GeographicGrid::Resampled GlobeSources::at(double latitudeDeg, double longitudeDeg,
                                           int level) const {
    // Sources are finest first, so among equals the finer one is kept.
    GeographicGrid::Resampled best;
    int bestRank = 3;  // 0 valid, 1 inside (a filled void), 2 an extended edge pixel, 3 none
    bool inside = false;
    for (const Source& source : m_sources) {
        const GeographicGrid::Resampled value = source.grid.at(latitudeDeg, longitudeDeg);
        inside = inside || (value.inside && source.finestFaceLevel >= level);
        const int rank = value.valid ? 0 : value.inside ? 1 : value.covered ? 2 : 3;
        if (rank < bestRank) {
            best = value;
            bestRank = rank;
        }
    }
    best.inside = inside;
    return best;
}

bool GlobeSources::wins(std::size_t k, std::int64_t col, std::int64_t row) const {
    const GeographicGrid& grid = m_sources[k].grid;
    if (!grid.validAt(col, row)) return false;
    for (std::size_t finer = 0; finer < k; ++finer)
        if (m_sources[finer].grid.at(grid.latitudeOf(row), grid.longitudeOf(col)).valid)
            return false;
    return true;
}

}  // namespace terrain::io
