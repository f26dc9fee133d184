// FullResolutionSurface: the ground truth the accuracy measures compare against (DESIGN.md,
// "Measurement is part of the product"): the pyramid's finest level — the DEM's own
// samples, no-data filled, exactly what every coarser level was subsampled from
// (docs/pyramid-format.md) — read patch by patch on the CPU, kept in an LRU within a byte
// budget, and evaluated at any world x, y of the DEM's extent as the full-resolution
// triangle mesh. It shares nothing with the LOD: no quadtree, no error
// bounds, no tessellation.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <list>
#include <memory>
#include <unordered_map>

namespace terrain::runtime {

/// The full-resolution surface above or below one world x, y. A DEM cell (four samples)
/// can be split into two triangles along either diagonal; the DEM does not say which, the
/// GPU tessellator picks its own, and the pyramid's error bounds hold for both
/// (docs/pyramid-format.md, "Error bounds").
struct SurfaceHeight {
    bool inside = false;  ///< x, y lies on the DEM's extent (else nothing below)
    /// The mesh the reference renderer draws: every cell split along the diagonal from its
    /// north-west to its south-east sample.
    double referenceM = 0.0;
    double lowM = 0.0;   ///< the lower of the two diagonals' heights at x, y
    double highM = 0.0;  ///< the higher (equal to lowM on a cell's edges and samples)
};

/// The lowest and highest heights of the full-resolution surface (either diagonal) over a
/// small area around a point.
struct HeightRange {
    bool inside = false;  ///< the area meets the DEM's extent (else nothing below)
    double lowM = 0.0;
    double highM = 0.0;
};

/// One thread (the render thread in the tools); move-only.
class FullResolutionSurface {
public:
    static constexpr std::size_t kDefaultBudgetBytes = std::size_t{512} << 20;

    /// Opens the pyramid (errors name it). `budgetBytes` bounds the finest patches kept.
    static Result<FullResolutionSurface> open(const std::filesystem::path& pyramid,
                                              std::size_t budgetBytes = kDefaultBudgetBytes);

    const TerrainGeometry& geometry() const { return *m_geometry; }
    const io::PyramidLayout& layout() const { return m_reader.layout(); }
    int finestLevel() const { return layout().finestLevel(); }

    /// A patch with heights (apron included), read on first use: the finest level's, or a
    /// coarser one's (the reference's footprint-filtered normals read them, ShadingTiles.h).
    /// The pointer is valid until the next call of patch() or heightAt(), which may evict
    /// it. Errors name the shard file and the patch.
    Result<const io::PatchRecord*> patch(const io::PatchId& id);

    /// A finest-level patch's summary (min/max height), cached: for culling.
    Result<io::PatchInfo> info(const io::PatchId& id);

    /// The surface at world x, y; inside = false beyond the DEM's extent (samples (0, 0) to
    /// (width − 1, height − 1)): the truth ends there, though the pyramid stores clamped
    /// copies of the edge beyond it and the LOD may draw them.
    Result<SurfaceHeight> heightAt(double x, double y);

    /// Half the side of the largest square heightRange() looks at, in samples: a bound on
    /// its cost (about (2r + 1)² evaluations), not on the tolerance. The measure asks for a
    /// square of a fraction of a pixel, so a pixel needs r samples only when it spans about
    /// 20 r; the pixels that see the DEM then shrink as r², and a frame's evaluations stay
    /// near its visible samples. Clipping the square only narrows the tolerance: the measure
    /// is then stricter, never looser. (It was 1 sample until Puget Sound read at 1 m
    /// spacing, seen from 44 km, needed 6: 4 pixels 8.1 px over at both ε, 0 px when the
    /// whole twentieth of a pixel was looked at.)
    static constexpr double kMaxRangeRadiusSamples = 256.0;

    /// The surface's range over the square of half-side `radiusM` (at most
    /// kMaxRangeRadiusSamples samples) around world x, y, clipped to the DEM's extent:
    /// exact (every vertex of the mesh's arrangement inside the square is visited).
    Result<HeightRange> heightRange(double x, double y, double radiusM);

    /// World x, y clamped into the DEM's extent (what heightAt calls inside).
    glm::dvec2 clampToDem(double x, double y) const;

    /// Height of finest-level sample (i, j) of the padded raster (clamped into it).
    Result<float> sample(std::int64_t i, std::int64_t j);

    std::size_t residentBytes() const { return m_residentBytes; }
    std::uint64_t patchReads() const { return m_patchReads; }

private:
    struct Entry {
        io::PatchId id;
        io::PatchRecord record;
        std::size_t bytes = 0;
    };
    using Lru = std::list<Entry>;  // most recently used first

    FullResolutionSurface(io::PyramidReader reader, std::size_t budgetBytes);

    /// heightAt() at sample coordinates inside the DEM's extent.
    Result<SurfaceHeight> heightAtSample(const glm::dvec2& sample);

    io::PyramidReader m_reader;
    std::unique_ptr<TerrainGeometry> m_geometry;  // stable address across moves
    std::size_t m_budgetBytes = 0;
    std::size_t m_residentBytes = 0;
    std::uint64_t m_patchReads = 0;
    Lru m_lru;
    std::unordered_map<io::PatchId, Lru::iterator, io::PatchIdHash> m_index;
    std::unordered_map<io::PatchId, io::PatchInfo, io::PatchIdHash> m_infos;
};

/// The height at fractions (fx, fy) ∈ [0, 1]² of a cell whose samples are h00 (north-west),
/// h10 (north-east), h01 (south-west), h11 (south-east): split along the north-west–
/// south-east diagonal (the reference mesh) or the other one.
double cellHeightNwSe(double h00, double h10, double h01, double h11, double fx, double fy);
double cellHeightNeSw(double h00, double h10, double h01, double h11, double fx, double fy);

}  // namespace terrain::runtime
