#include "terrain/build/GlobeSourceSurface.h"

#include "GlobeSources.h"

namespace terrain::io {

GlobeSourceSurface::GlobeSourceSurface(std::unique_ptr<GlobeSources> sources)
    : m_sources(std::move(sources)) {}
GlobeSourceSurface::GlobeSourceSurface(GlobeSourceSurface&&) noexcept = default;
GlobeSourceSurface& GlobeSourceSurface::operator=(GlobeSourceSurface&&) noexcept = default;
GlobeSourceSurface::~GlobeSourceSurface() = default;

Result<GlobeSourceSurface> GlobeSourceSurface::read(std::span<DemReader* const> sources,
                                                    std::uint64_t memoryBudgetBytes,
                                                    int patchQuads) {
    Result<GlobeSources> read = GlobeSources::read(sources, memoryBudgetBytes, patchQuads, 0);
    if (!read) return read.error();
    return GlobeSourceSurface(std::make_unique<GlobeSources>(std::move(read).value()));
}

std::pair<double, double> GlobeSourceSurface::heightsAt(double latitudeDeg,
                                                        double longitudeDeg) const {
    return m_sources->surfaceHeightsAt(latitudeDeg, longitudeDeg).value_or(std::pair{0.0, 0.0});
}

}  // namespace terrain::io

namespace terrain::io {

std::vector<ManifestSeam> GlobeSourceSurface::seams() const { return m_sources->seams(); }

}  // namespace terrain::io
