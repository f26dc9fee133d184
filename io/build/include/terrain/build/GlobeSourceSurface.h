// GlobeSourceSurface: the full-resolution surface of a globe pyramid's sources, the ground
// truth its drawn error is measured against (runtime/truth, GlobeTruth): the
// sources composited as the builder composites them (GlobePyramidBuilder.h), each drawn as the
// triangles between its pixel centres, heights along the ellipsoid normal. Where no source
// covers a place the truth is the bare ellipsoid (height 0).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace terrain::io {

class GlobeSources;

class GlobeSourceSurface {
public:
    /// Reads the sources whole (each within memoryBudgetBytes / count); `patchQuads` as the
    /// pyramid's (it and the build's oversampling set each source's finest face level, which
    /// decides nothing about the full-resolution surface).
    static Result<GlobeSourceSurface> read(std::span<DemReader* const> sources,
                                           std::uint64_t memoryBudgetBytes, int patchQuads);
    GlobeSourceSurface(GlobeSourceSurface&&) noexcept;
    GlobeSourceSurface& operator=(GlobeSourceSurface&&) noexcept;
    ~GlobeSourceSurface();

    /// The surface's heights at a place for the two diagonals of its cell (a–d, b–c), metres;
    /// (0, 0) where no source covers it.
    std::pair<double, double> heightsAt(double latitudeDeg, double longitudeDeg) const;

    /// Where each source is blended into a coarser one at its edges, as the builder writes it
    /// to the manifest (globe.seams).
    std::vector<ManifestSeam> seams() const;

private:
    explicit GlobeSourceSurface(std::unique_ptr<GlobeSources> sources);
    std::unique_ptr<GlobeSources> m_sources;
};

}  // namespace terrain::io
