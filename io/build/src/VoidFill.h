// VoidFill: the no-data voids of one source and their fill (docs/pyramid-format.md,
// "No-data"), as a cartographer fills SRTM's: a void over another source takes that source's
// surface plus the difference between the two at the void's rim, spread smoothly into the
// void (the delta-surface fill, Grohman, Kroenung & Strebeck 2006, "Filling SRTM voids: the
// delta surface fill method"); a void with nothing beneath it takes the membrane from its
// whole rim (MembraneFill.h; gdal_fillnodata fills from every direction in the same spirit).
// A void is a 4-connected run of no-data samples; its rim, the valid samples beside it. A void
// that reaches the raster's edge is filled from the rim it has. Each void is solved alone from
// its own box (one sample around it), so every part of a build (a row, a block, a shard, a
// region build's process) fills it to the same bits.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace terrain::io::detail {

class VoidFill {
public:
    /// The source's samples of a window, as DemReader::readWindow gives them (NaN: no data).
    using ReadWindow = std::function<Status(std::int64_t x0, std::int64_t y0, std::int64_t width,
                                            std::int64_t rows, std::span<float> out)>;
    /// The surface beneath the source at its sample (column, row): the composite of the sources
    /// under it, or nothing where none is.
    using Beneath = std::function<std::optional<double>(std::int64_t column, std::int64_t row)>;

    /// Finds the voids of a `width` × `height` source and fills each: over `beneath` where it
    /// gives a height at every sample of the void and its rim, else by the membrane. One pass
    /// over the rows, then each void's box read again (at most kMaxSolveSamples of it held: a
    /// larger void is solved on a grid coarsened by a power of two, interpolated back).
    static Result<VoidFill> find(std::int64_t width, std::int64_t height, const ReadWindow& read,
                                 const Beneath* beneath = nullptr);
    /// The voids of a reader's raster (no source beneath).
    static Result<VoidFill> find(DemReader& reader);

    /// The fill of no-data sample (column, row). `beneath`: the one `find` had, if it had one.
    float at(std::int64_t column, std::int64_t row, const Beneath* beneath = nullptr) const;

    /// Every no-data sample of the source; those filled over the source beneath.
    std::int64_t samples() const { return m_samples; }
    std::int64_t samplesOverBeneath() const { return m_samplesOverBeneath; }
    std::int64_t voids() const { return static_cast<std::int64_t>(m_voids.size()); }

    /// The largest box side solved at full resolution is sqrt of this.
    static constexpr std::int64_t kMaxSolveSamples = std::int64_t{1} << 20;

private:
    struct Run {
        std::int64_t x0 = 0, x1 = 0;  // no-data columns [x0, x1) of its row
        std::int32_t voidIndex = 0;
        std::int64_t firstValue = -1;  // into m_values, or −1: the void was solved coarsened
    };
    struct Void {
        std::int64_t x0 = 0, y0 = 0, width = 0, height = 0;  // its box, rim included
        std::int64_t step = 1;  // of the grid it was solved on (coarse: step > 1)
        std::int64_t coarseWidth = 0, coarseHeight = 0;
        std::vector<float> coarse;  // the solution there (step > 1)
        bool overBeneath = false;   // solved as the difference to the surface beneath
        std::int64_t samples = 0;
    };
    Status solve(Void& v, std::int32_t index, const ReadWindow& read, const Beneath* beneath);
    float coarseAt(const Void& v, std::int64_t column, std::int64_t row) const;
    const Run* runAt(std::int64_t column, std::int64_t row) const;

    std::vector<Run> m_runs;              // row by row, west to east
    std::vector<std::int64_t> m_rowRuns;  // row r's runs: [m_rowRuns[r], m_rowRuns[r + 1])
    std::vector<Void> m_voids;
    std::vector<float> m_values;  // the fill of full-resolution voids, run by run
    std::int64_t m_samples = 0, m_samplesOverBeneath = 0;
};

/// Marks each of `heights` valid (1) or no-data (0, NaN) in `valid`; the no-data count.
inline std::int64_t markValidSamples(std::span<const float> heights,
                                     std::span<std::uint8_t> valid) {
    std::int64_t missing = 0;
    for (std::size_t i = 0; i < heights.size(); ++i) {
        valid[i] = std::isnan(heights[i]) ? 0 : 1;
        missing += 1 - valid[i];
    }
    return missing;
}

}  // namespace terrain::io::detail
