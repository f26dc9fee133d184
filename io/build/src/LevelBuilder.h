// LevelBuilder: the planar build's pass over one level, or over a rectangle of one level's
// patches (a shard of a region build, PyramidShards.h). It walks the rectangle in bands of
// two patch rows (plus the one-sample apron) and
//  - writes the band's patches (heights, mask, λ(d), summary) to their shards,
//  - measures each patch's share of its parent's Err_Int (the parent's coarse cells that
//    lie in it, Yusov & Shevtsov 2011, §4),
//  - hands the band's even samples to the next coarser level: h^(l−1)_{i,j} ≡ h^(l)_{2i,2j}.
// Err_Appr(P) = Err_Int(P) + max over children Err_Appr (§4, nested like ROAM's wedgies) is
// then known when the coarser level's pass reaches P. A coarse cell of P lies in exactly one
// child (N − 1 is even), and Err_Int is a maximum over cells rounded up to a float, so the
// maximum of the children's shares is Err_Int bit for bit: the whole build and a region
// build agree whichever patches a band or a shard holds.
#pragma once

#include "BuildClock.h"
#include "DemStatistics.h"
#include "OriginalSampleDistances.h"
#include "ParallelFor.h"
#include "RowFill.h"
#include "terrain/base/Assert.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/build/NoDataFill.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/ShardWriter.h"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <system_error>
#include <vector>

namespace terrain::io::detail {

/// Patches [x0, x1) × [y0, y1) of one level.
struct PatchRect {
    std::int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    std::int64_t countX() const { return x1 - x0; }
    std::int64_t countY() const { return y1 - y0; }
};

// Rows [firstRow, firstRow + rows) of one level's padded raster, columns firstColumn …
// firstColumn + width − 1 stored from index 0 (firstColumn −1: the west apron).
struct Band {
    std::int64_t firstRow = 0;
    std::int64_t rows = 0;
    std::int64_t firstColumn = -1;
    std::int64_t width = 0;
    std::vector<float> heights;
    std::vector<std::uint8_t> valid;

    float* heightRow(std::int64_t row) { return heights.data() + (row - firstRow) * width; }
    std::uint8_t* validRow(std::int64_t row) { return valid.data() + (row - firstRow) * width; }
};

/// The band's columns for the patches [rect.x0, rect.x1) with their aprons.
inline void shapeBand(Band& band, const PatchRect& rect, int patchQuads) {
    band.firstColumn = rect.x0 * patchQuads - 1;
    band.width = rect.countX() * patchQuads + 3;
    band.heights.resize(static_cast<std::size_t>((2 * patchQuads + 3) * band.width));
    band.valid.resize(band.heights.size());
}

/// The DEM's filled last column (x = W − 1) and last row (y = H − 1): the samples beyond the
/// DEM copy them at every level.
class DemEdgeSamples {
public:
    virtual ~DemEdgeSamples() = default;
    virtual Result<float> lastColumn(std::int64_t row) = 0;
    virtual Result<float> lastRow(std::int64_t column) = 0;
};

/// What the finest pass keeps of the edges, for the samples of its rows and columns.
struct DemEdges final : DemEdgeSamples {
    std::int64_t firstRow = 0;
    std::vector<float> lastColumnHeights;  // rows firstRow …, where the pass reached x = W − 1
    std::int64_t firstColumn = 0;
    std::vector<float> lastRowHeights;  // columns firstColumn …, where the pass reached y = H − 1

    Result<float> lastColumn(std::int64_t row) override {
        return lastColumnHeights.at(static_cast<std::size_t>(row - firstRow));
    }
    Result<float> lastRow(std::int64_t column) override {
        return lastRowHeights.at(static_cast<std::size_t>(column - firstColumn));
    }
};

/// The DEM samples a pass counts in the statistics and keeps edges of: each sample is owned
/// by one region, so region builds add up to the whole build's counts.
struct OwnedSamples {
    std::int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) × [y0, y1), within the DEM
};

// Produces rows of a level's padded raster. Samples beyond the DEM take the value of the
// nearest DEM sample in DEM (finest-level) coordinates, so the even-sample relation
// between levels holds there too; they are marked invalid.
class LevelRows {
public:
    virtual ~LevelRows() = default;
    virtual Status fetch(Band& band) = 0;  // fills band.firstRow … + rows
};

class FinestRows final : public LevelRows {
public:
    FinestRows(DemReader& reader, SourceVoids& voids, const OwnedSamples& owned, DemEdges& edges,
               DemStatistics& stats)
        : m_reader(reader),
          m_w(reader.info().width),
          m_h(reader.info().height),
          m_owned(owned),
          m_edges(edges),
          m_stats(stats),
          m_fill(voids, wholeSourceUnits(reader.info())) {
        m_edges.firstRow = owned.y0;
        m_edges.lastColumnHeights.assign(static_cast<std::size_t>(owned.y1 - owned.y0), 0.0f);
        m_nextStatisticsRow = owned.y0;
    }

    Status fetch(Band& band) override {
        const std::int64_t first = std::max<std::int64_t>(band.firstRow, 0);
        const std::int64_t last = std::min(band.firstRow + band.rows, m_h);  // exclusive
        // DEM columns [a, b) of the band.
        const std::int64_t a = std::max<std::int64_t>(band.firstColumn, 0);
        const std::int64_t b = std::min(band.firstColumn + band.width, m_w);
        const std::int64_t columns = b - a;
        if (last > first) {
            m_scratch.resize(static_cast<std::size_t>((last - first) * columns));
            if (auto read = m_reader.readWindow(a, first, columns, last - first, m_scratch); !read)
                return read;
        }
        for (std::int64_t r = band.firstRow; r < band.firstRow + band.rows; ++r) {
            float* out = band.heightRow(r);
            std::uint8_t* valid = band.validRow(r);
            if (r >= 0 && r < m_h) {
                std::span<float> row(out + (a - band.firstColumn),
                                     static_cast<std::size_t>(columns));
                std::span<std::uint8_t> rowValid(valid + (a - band.firstColumn), row.size());
                std::copy_n(m_scratch.data() + (r - first) * columns, columns, row.data());
                Result<std::int64_t> filled = m_fill.fill(r, a, row, rowValid);
                if (!filled) return filled.error();
                if (r >= m_nextStatisticsRow && r < m_owned.y1) {  // bands overlap by their aprons
                    countStatistics(a, row, rowValid);
                    if (b == m_w)
                        m_edges.lastColumnHeights[static_cast<std::size_t>(r - m_owned.y0)] =
                            row.back();
                    m_nextStatisticsRow = r + 1;
                }
                padRow(band, out, valid);
                if (r == m_h - 1) {
                    m_lastRow.assign(out, out + band.width);
                    m_edges.firstColumn = a;
                    m_edges.lastRowHeights.assign(row.begin(), row.end());
                }
            } else if (r >= m_h) {
                // Below the DEM: the nearest DEM row, H − 1.
                TERRAIN_ASSERT(!m_lastRow.empty(), "rows are fetched top to bottom");
                std::copy(m_lastRow.begin(), m_lastRow.end(), out);
                std::fill_n(valid, band.width, std::uint8_t{0});
            }
        }
        if (band.firstRow < 0) {  // the apron row −1 copies row 0, which the band also holds
            std::copy_n(band.heightRow(0), band.width, band.heightRow(-1));
            std::fill_n(band.validRow(-1), band.width, std::uint8_t{0});
        }
        return {};
    }

private:
    // Columns west of the DEM copy x = 0, those east of it x = W − 1.
    void padRow(const Band& band, float* out, std::uint8_t* valid) const {
        for (std::int64_t c = 0; c < band.width; ++c) {
            const std::int64_t x = band.firstColumn + c;
            if (x >= 0 && x < m_w) continue;
            out[c] = out[std::clamp<std::int64_t>(x, 0, m_w - 1) - band.firstColumn];
            valid[c] = 0;
        }
    }

    void countStatistics(std::int64_t a, std::span<const float> row,
                         std::span<const std::uint8_t> valid) {
        const std::int64_t from = std::max(m_owned.x0, a) - a;
        const std::int64_t to = std::min<std::int64_t>(m_owned.x1 - a, std::ssize(row));
        for (std::int64_t i = from; i < to; ++i) {
            const auto k = static_cast<std::size_t>(i);
            if (!valid[k]) {
                ++m_stats.noDataSamples;
                continue;
            }
            ++m_stats.validSamples;
            m_stats.minHeight = std::min(m_stats.minHeight, double(row[k]));
            m_stats.maxHeight = std::max(m_stats.maxHeight, double(row[k]));
        }
    }

    DemReader& m_reader;
    std::int64_t m_w, m_h;
    OwnedSamples m_owned;
    DemEdges& m_edges;
    DemStatistics& m_stats;
    // The documented fill, the same whichever band or region reads the row.
    RowFill m_fill;
    std::vector<float> m_scratch;
    std::vector<float> m_lastRow;  // padded row H − 1 (with apron)
    std::int64_t m_nextStatisticsRow = 0;
};

/// Where a coarser level's even samples go: rows [originY, originY + height) of columns
/// [originX, originX + width) of that level's samples on the DEM, appended top to bottom.
class EvenRows {
public:
    virtual ~EvenRows() = default;
    virtual std::int64_t originX() const = 0;
    virtual std::int64_t originY() const = 0;
    virtual std::int64_t width() const = 0;
    virtual std::int64_t height() const = 0;
    virtual std::int64_t rowsWritten() const = 0;
    virtual Status appendRow(const float* heights, const std::uint8_t* valid) = 0;
};

/// A level's samples on the DEM ("inside": i·step ≤ W − 1, j·step ≤ H − 1), to read back.
class InsideSamples {
public:
    virtual ~InsideSamples() = default;
    virtual std::int64_t width() const = 0;   // of the whole level, columns from 0
    virtual std::int64_t height() const = 0;  // rows from 0
    /// Columns [x0, x0 + count) of `row`.
    virtual Status readRow(std::int64_t row, std::int64_t x0, std::int64_t count, float* heights,
                           std::uint8_t* valid) = 0;
};

// The whole build's inside samples of one level, as a temporary file of float32 rows plus
// one of mask bytes, written by the finer level's pass and read back band by band.
class InsideRaster final : public EvenRows, public InsideSamples {
public:
    static Result<std::unique_ptr<InsideRaster>> create(const std::filesystem::path& path,
                                                        std::int64_t width, std::int64_t height) {
        auto r = std::unique_ptr<InsideRaster>(new InsideRaster);
        r->m_path = path;
        r->m_width = width;
        r->m_height = height;
        r->m_heights = std::fopen(path.c_str(), "w+b");
        r->m_valid = std::fopen((path.string() + ".valid").c_str(), "w+b");
        if (r->m_heights == nullptr || r->m_valid == nullptr)
            return Error{path.string() + ": cannot create temporary level raster: " +
                         std::generic_category().message(errno)};
        return r;
    }
    InsideRaster(const InsideRaster&) = delete;
    InsideRaster& operator=(const InsideRaster&) = delete;
    ~InsideRaster() override {
        if (m_heights != nullptr) std::fclose(m_heights);
        if (m_valid != nullptr) std::fclose(m_valid);
        std::error_code ec;
        if (!m_path.empty()) {
            std::filesystem::remove(m_path, ec);
            std::filesystem::remove(m_path.string() + ".valid", ec);
        }
    }

    std::int64_t originX() const override { return 0; }
    std::int64_t originY() const override { return 0; }
    std::int64_t width() const override { return m_width; }
    std::int64_t height() const override { return m_height; }
    std::int64_t rowsWritten() const override { return m_rowsWritten; }

    Status appendRow(const float* heights, const std::uint8_t* valid) override {
        const auto n = static_cast<std::size_t>(m_width);
        if (std::fwrite(heights, sizeof(float), n, m_heights) != n ||
            std::fwrite(valid, 1, n, m_valid) != n)
            return Error{m_path.string() + ": cannot write temporary level raster: " +
                         std::generic_category().message(errno)};
        ++m_rowsWritten;
        return {};
    }

    Status readRow(std::int64_t row, std::int64_t x0, std::int64_t count, float* heights,
                   std::uint8_t* valid) override {
        const auto n = static_cast<std::size_t>(count);
        const auto fdHeights = fileno(m_heights), fdValid = fileno(m_valid);
        const off_t at = row * m_width + x0;
        if (pread(fdHeights, heights, n * sizeof(float), at * off_t{sizeof(float)}) !=
                static_cast<ssize_t>(n * sizeof(float)) ||
            pread(fdValid, valid, n, at) != static_cast<ssize_t>(n))
            return Error{m_path.string() + ": cannot read temporary level raster row " +
                         std::to_string(row)};
        return {};
    }

    Status flush() {
        if (std::fflush(m_heights) != 0 || std::fflush(m_valid) != 0)
            return Error{m_path.string() + ": cannot write temporary level raster: " +
                         std::generic_category().message(errno)};
        return {};
    }

private:
    InsideRaster() = default;
    std::filesystem::path m_path;
    std::int64_t m_width = 0, m_height = 0;
    std::FILE* m_heights = nullptr;
    std::FILE* m_valid = nullptr;
    std::int64_t m_rowsWritten = 0;
};

// Rows of a level coarser than the finest: the inside samples, and beyond the DEM the
// DEM's filled edge samples (the nearest DEM sample in DEM coordinates).
class CoarseRows final : public LevelRows {
public:
    CoarseRows(InsideSamples& inside, DemEdgeSamples& edges, std::int64_t step,
               std::int64_t demWidth)
        : m_inside(inside), m_edges(edges), m_step(step), m_demWidth(demWidth) {}

    Status fetch(Band& band) override {
        const std::int64_t a = std::max<std::int64_t>(band.firstColumn, 0);
        const std::int64_t end = band.firstColumn + band.width;
        const std::int64_t insideEnd = std::min(end, m_inside.width());
        for (std::int64_t r = band.firstRow; r < band.firstRow + band.rows; ++r) {
            float* out = band.heightRow(r) - band.firstColumn;  // indexed by column
            std::uint8_t* valid = band.validRow(r) - band.firstColumn;
            const std::int64_t row = std::max<std::int64_t>(r, 0);  // apron row −1 → row 0
            if (row < m_inside.height()) {
                if (insideEnd > a)
                    if (auto read = m_inside.readRow(row, a, insideEnd - a, out + a, valid + a);
                        !read)
                        return read;
                if (end > std::max(a, insideEnd)) {
                    Result<float> edge = m_edges.lastColumn(row * m_step);
                    if (!edge) return edge.error();
                    for (std::int64_t i = std::max(a, insideEnd); i < end; ++i) {
                        out[i] = edge.value();
                        valid[i] = 0;
                    }
                }
            } else {
                for (std::int64_t i = a; i < end; ++i) {
                    Result<float> edge = m_edges.lastRow(std::min(i * m_step, m_demWidth - 1));
                    if (!edge) return edge.error();
                    out[i] = edge.value();
                    valid[i] = 0;
                }
            }
            if (band.firstColumn < 0) {
                out[-1] = out[0];
                valid[-1] = 0;
            }
            if (r < 0) std::fill_n(band.validRow(r), band.width, std::uint8_t{0});
        }
        return {};
    }

private:
    InsideSamples& m_inside;
    DemEdgeSamples& m_edges;
    std::int64_t m_step, m_demWidth;
};

// Patch-indexed grid of floats for patches [x0, x0 + width) × [y0, y0 + height) of a level.
struct LevelGrid {
    std::int64_t x0 = 0, y0 = 0, width = 0, height = 0;
    std::vector<float> values;
    void reset(const PatchRect& rect) {
        x0 = rect.x0;
        y0 = rect.y0;
        width = rect.countX();
        height = rect.countY();
        values.assign(static_cast<std::size_t>(width * height), 0.0f);
    }
    std::int64_t endX() const { return x0 + width; }
    std::int64_t endY() const { return y0 + height; }
    float& at(std::int64_t x, std::int64_t y) {
        return values[static_cast<std::size_t>((y - y0) * width + (x - x0))];
    }
    float at(std::int64_t x, std::int64_t y) const {
        return values[static_cast<std::size_t>((y - y0) * width + (x - x0))];
    }
};

/// What a pass tells the coarser level's pass about its patches.
struct ChildBounds {
    LevelGrid approx;         ///< Err_Appr
    LevelGrid interpolation;  ///< the patch's share of its parent's Err_Int
};

class LevelBuilder {
public:
    /// `voids`: the reader's, shared by the passes and regions of one process.
    LevelBuilder(DemReader& reader, SourceVoids& voids, const PyramidLayout& layout,
                 const PyramidBuildOptions& options, const std::filesystem::path& folder,
                 bool withMask)
        : m_reader(reader),
          m_voids(voids),
          m_original(reader.originalSamples()),
          m_layout(layout),
          m_options(options),
          m_folder(folder),
          m_withMask(withMask),
          m_threads(options.threads > 0 ? options.threads
                                        : std::max(1u, std::thread::hardware_concurrency())) {
        m_shardOptions.compressionLevel = options.compressionLevel;
        m_shardOptions.units.source = reader.info().vertical;  // the manifest's
        if (options.maxErrorM > 0.0) m_quantization = ManifestQuantization{options.maxErrorM};
        for (int l = 0; l < m_layout.levelCount(); ++l)
            m_totalSamples += double(m_layout.levelSamplesX(l)) * double(m_layout.levelSamplesY(l));
        m_levelMaxError.assign(static_cast<std::size_t>(m_layout.levelCount()), 0.0f);
    }

    /// The whole pyramid, finest level first, in bands across its full width.
    Status run() {
        const int finest = m_layout.finestLevel();
        const std::int64_t w = m_reader.info().width, h = m_reader.info().height;
        std::unique_ptr<InsideRaster> inside;  // the current level's samples (coarse levels)
        for (int level = finest; level >= 0; --level) {
            std::unique_ptr<InsideRaster> coarser;
            if (level > 0) {
                const std::int64_t step = m_layout.levelStep(level - 1);
                auto made =
                    InsideRaster::create(m_folder / "tmp" / fmt::format("level-{}.raw", level - 1),
                                         (w - 1) / step + 1, (h - 1) / step + 1);
                if (!made) return made.error();
                coarser = std::move(made).value();
            }
            const PatchRect whole{0, 0, m_layout.patchesX(level), m_layout.patchesY(level)};
            std::unique_ptr<LevelRows> rows;
            if (level == finest)
                rows = std::make_unique<FinestRows>(m_reader, m_voids, OwnedSamples{0, 0, w, h},
                                                    m_edges, m_statistics);
            else
                rows = std::make_unique<CoarseRows>(*inside, m_edges, m_layout.levelStep(level), w);
            if (auto pass = runLevel(level, whole, *rows, coarser.get()); !pass) return pass;
            if (coarser != nullptr) {
                if (auto flushed = coarser->flush(); !flushed) return flushed;
                TERRAIN_ASSERT(coarser->rowsWritten() == coarser->height());
            }
            rows.reset();
            m_children = std::move(m_bounds);
            inside = std::move(coarser);
        }
        return {};
    }

    /// The finest level's patches `rect` (a region build), from the source: the statistics
    /// and edges() of the DEM samples it `owned`; its even samples go to `coarser` (null
    /// when the finest level is the root). bounds() then holds the rectangle's.
    Status runFinestRegion(const PatchRect& rect, const OwnedSamples& owned, EvenRows* coarser) {
        TERRAIN_ASSERT(m_original == nullptr, "region builds of resampled sources are refused");
        FinestRows rows(m_reader, m_voids, owned, m_edges, m_statistics);
        return runLevel(m_layout.finestLevel(), rect, rows, coarser);
    }

    /// A coarser level's patches `rect`: `rows` gives its samples, `children` the bounds of
    /// its children, and its even samples go to `coarser` (null at level 0).
    Status runCoarseRegion(int level, const PatchRect& rect, LevelRows& rows, ChildBounds children,
                           EvenRows* coarser) {
        TERRAIN_ASSERT(m_original == nullptr, "region builds of resampled sources are refused");
        m_children = std::move(children);
        return runLevel(level, rect, rows, coarser);
    }

    const DemStatistics& statistics() const { return m_statistics; }
    const DemEdges& edges() const { return m_edges; }
    const ChildBounds& bounds() const { return m_bounds; }
    std::int64_t patches() const { return m_patches; }
    float rootError() const { return m_levelMaxError[0]; }
    const std::vector<float>& levelMaxError() const { return m_levelMaxError; }
    /// A resampled source's own valid samples, and their largest distance from the finest
    /// level's surface.
    std::int64_t originalValidSamples() const { return m_originalValid; }
    double originalFinestDistance() const { return m_originalFinestDistance; }
    /// Set for a lossy build, with the largest difference the finest level's quantizer made.
    const std::optional<ManifestQuantization>& quantization() const { return m_quantization; }
    const PyramidBuildPhases& phases() const { return m_phases; }

private:
    Status runLevel(int level, const PatchRect& rect, LevelRows& rows, EvenRows* coarser) {
        const int q = m_layout.patchQuads();
        const std::int64_t patchesY = m_layout.patchesY(level);
        const std::int64_t countX = rect.countX();

        m_bounds.approx.reset(rect);
        m_bounds.interpolation.reset(rect);
        if (m_original != nullptr) m_error.reset(rect);

        Band band;
        shapeBand(band, rect, q);
        std::vector<PatchRecord> records(static_cast<std::size_t>(2 * countX));
        std::map<std::pair<std::int64_t, std::int64_t>, ShardWriter> writers;  // by (row, column)

        for (std::int64_t firstPatchRow = rect.y0; firstPatchRow < rect.y1; firstPatchRow += 2) {
            if (m_options.cancel != nullptr && m_options.cancel->load())
                return Error{m_folder.string() + ": build interrupted"};
            const int patchRows =
                static_cast<int>(std::min<std::int64_t>(2, rect.y1 - firstPatchRow));
            band.firstRow = firstPatchRow * q - 1;
            band.rows = patchRows * q + 3;
            auto phaseStart = BuildClock::now();
            if (auto fetched = rows.fetch(band); !fetched) return fetched;
            m_phases.readSeconds += secondsSince(phaseStart);
            phaseStart = BuildClock::now();

            // Patches of the band, in parallel.
            const std::int64_t count = patchRows * countX;
            m_quantized.assign(static_cast<std::size_t>(count), 0.0);
            m_parentSamples.resize(static_cast<std::size_t>(count));
            parallelFor(count, m_threads, [&](std::int64_t i) {
                m_quantized[static_cast<std::size_t>(i)] = makeRecord(
                    level, band, PatchId{level, rect.x0 + i % countX, firstPatchRow + i / countX},
                    records[static_cast<std::size_t>(i)],
                    m_parentSamples[static_cast<std::size_t>(i)]);
            });
            if (m_quantization && level == m_layout.finestLevel())
                for (const double d : m_quantized)
                    m_quantization->finestLargestErrorM =
                        std::max(m_quantization->finestLargestErrorM, d);
            if (m_original != nullptr) {
                if (auto raised = coverOriginalSamples(level, firstPatchRow, patchRows, records);
                    !raised)
                    return raised;
            }
            if (coarser != nullptr)
                if (auto written = writeCoarserRows(band, *coarser); !written) return written;
            m_phases.boundsSeconds += secondsSince(phaseStart);
            phaseStart = BuildClock::now();
            // The band's patches coded and compressed on every thread (the records are final:
            // coverOriginalSamples may have raised their bounds), then written in order.
            const ShardWriterOptions levelOptions = shardOptionsOf(level);
            m_encoded.resize(records.size());
            parallelFor(count, m_threads, [&](std::int64_t i) {
                const auto k = static_cast<std::size_t>(i);
                encodePatch(records[k], m_parentSamples[k], m_layout, m_withMask, levelOptions,
                            m_encoded[k]);
            });
            if (auto written = writeRecords(level, records, count, writers); !written)
                return written;
            // A shard is complete once the band has passed its last patch row.
            const std::int64_t lastPatchRow = firstPatchRow + patchRows - 1;
            for (auto it = writers.begin(); it != writers.end();) {
                const std::int64_t shardLastRow =
                    std::min((it->first.first + 1) * m_layout.shardPatches(), patchesY) - 1;
                if (shardLastRow > lastPatchRow) break;  // ordered by shard row
                if (auto done = it->second.finish(); !done) return done;
                it = writers.erase(it);
            }
            m_phases.writeSeconds += secondsSince(phaseStart);
            m_doneSamples += double(patchRows * q) * double(band.width - 2);
            if (m_options.progress)
                m_options.progress({level, std::min(1.0, m_doneSamples / m_totalSamples)});
        }
        TERRAIN_ASSERT(writers.empty(), "every shard of the rectangle is finished");
        m_childError = m_error;
        return {};
    }

    // A lossy build's stored heights of `level`: Yusov's quantizer (§4) rounds them in place;
    // returns the largest difference it made, or nothing where the level keeps the source's
    // own units: a source whose units are at least the step (the Puget Sound JPEG's 25.7 m)
    // is stored exactly, in its units, since rounding them to the step would only make codes
    // larger.
    std::optional<double> storeAtLevel(int level, std::span<float> heights) const {
        const double halfStep = m_quantization->halfStep(level, m_layout.finestLevel());
        const VerticalTransform& units = m_reader.info().vertical;
        const bool coarseUnits =
            units != VerticalTransform{} && std::abs(units.scale) >= 2.0 * halfStep;
        if (coarseUnits) return std::nullopt;
        return quantizeHeights(heights, halfStep);
    }

    // Returns the largest difference the quantizer made to the patch's samples (0 when
    // lossless). `parentSamples` become the heights the parent patch will be stored with at
    // the patch's odd sample indices (HeightCodes.h): the level's even samples, which the
    // coarser level keeps, stored as that level stores them.
    double makeRecord(int level, Band& band, const PatchId& id, PatchRecord& record,
                      std::vector<float>& parentSamples) {
        const int n = m_layout.patchSamples(), t = m_layout.tileSamples(),
                  q = m_layout.patchQuads();
        record.id = id;
        record.heights.resize(static_cast<std::size_t>(t * t));
        // The flags are copied even without a mask to store: they mark the overhanging
        // samples, which noDataSamples counts. clear() keeps the storage for the next patch.
        record.valid.resize(static_cast<std::size_t>(t * t));
        const std::int64_t x0 = id.x * q - 1 - band.firstColumn;  // band index of the apron
        for (int j = 0; j < t; ++j) {
            const std::int64_t row = id.y * q - 1 + j;
            std::copy_n(band.heightRow(row) + x0, t, record.heights.data() + j * t);
            std::copy_n(band.validRow(row) + x0, t, record.valid.data() + j * t);
        }
        // The patch's share of its parent's Err_Int (Yusov §4), from the exact heights: the
        // parent's coarse cells in this patch against its samples.
        if (level > 0)
            m_bounds.interpolation.at(id.x, id.y) =
                simplificationError(GridView{record.heights.data() + t + 1, n, t}, 0, 0, q, q, 2);
        parentSamples.clear();
        if (level > 0 && m_options.parentPrediction) {
            oddIndexSamples(record.heights, t, parentSamples);
            if (m_quantization) storeAtLevel(level - 1, parentSamples);
        }
        // A lossy build stores the quantized heights (Yusov §4), so everything below that
        // describes what is drawn (min/max, λ(d), the checksum) describes them; Err_Appr
        // stays the exact heights' (from the band), and δ_l joins it in Err(P).
        double quantized = 0.0;
        float quantError = 0.0f;
        if (m_quantization) {
            if (const std::optional<double> largest = storeAtLevel(level, record.heights)) {
                quantized = *largest;
                quantError = roundUpToFloat(
                    std::max(m_quantization->halfStep(level, m_layout.finestLevel()), quantized));
            }
        }
        PatchInfo& info = record.info;
        info = PatchInfo{};
        info.present = true;
        summariseDrawnSamples(m_layout, record.heights, record.valid, info);
        if (!m_withMask) record.valid.clear();
        const GridView interior{record.heights.data() + t + 1, n, t};
        record.blockErrors.resize(
            static_cast<std::size_t>(m_layout.blocksPerSide() * m_layout.blocksPerSide()));
        patchBlockErrors(interior, m_layout.blockQuads(), record.blockErrors);

        // Err_Appr(P) = Err_Int(P) + max over children Err_Appr (Yusov §4), Err_Int(P) the
        // largest of the children's shares.
        float approx = 0.0f;
        if (level < m_layout.finestLevel()) {
            const ChildBounds& c = m_children;
            float worstChild = 0.0f, interpolation = 0.0f;
            for (std::int64_t cy = 2 * id.y; cy < std::min(2 * id.y + 2, c.approx.endY()); ++cy)
                for (std::int64_t cx = 2 * id.x; cx < std::min(2 * id.x + 2, c.approx.endX());
                     ++cx) {
                    worstChild = std::max(worstChild, c.approx.at(cx, cy));
                    interpolation = std::max(interpolation, c.interpolation.at(cx, cy));
                }
            approx = roundUpSum(interpolation, worstChild);
        } else if (m_options.finestErrorFloor) {
            approx = std::max(approx, m_options.finestErrorFloor(id.x, id.y));
        }
        m_bounds.approx.at(id.x, id.y) = approx;
        info.approxError = approx;
        // Err(P) = Err_Appr(P) + δ_l (Yusov §4): the stored surface is within δ_l of the
        // exact one at every sample, so between them too.
        info.quantError = quantError;
        info.error = roundUpSum(approx, quantError);
        return quantized;
    }

    // A resampled source (issue 21): Err(P) is raised to cover the source's own samples
    // lying in P, measured against P's surface (OriginalSampleDistances.h), and to its
    // children's Err, so the bound still shrinks from a patch to its children. Err_Appr
    // stays Yusov's: the bound against the resampled grid. Whole builds only (full rows).
    Status coverOriginalSamples(int level, std::int64_t firstPatchRow, int patchRows,
                                std::vector<PatchRecord>& records) {
        const std::int64_t patchesX = m_layout.patchesX(level);
        const std::size_t count = static_cast<std::size_t>(patchRows * patchesX);
        m_distances.assign(count, 0.0);
        const bool finest = level == m_layout.finestLevel();
        const auto patchAt = [&](std::int64_t px, std::int64_t py) -> const PatchRecord& {
            return records[static_cast<std::size_t>((py - firstPatchRow) * patchesX + px)];
        };
        const auto visit = [&](const PatchRecord& patch, std::int64_t, std::int64_t,
                               double distance) {
            double& worst = m_distances[static_cast<std::size_t>(&patch - records.data())];
            worst = std::max(worst, distance);
            if (finest) {
                ++m_originalValid;
                m_originalFinestDistance = std::max(m_originalFinestDistance, distance);
            }
        };
        if (Status visited =
                detail::visitOriginalSamples(*m_original, *m_reader.info().resampledFrom, m_layout,
                                             level, firstPatchRow, patchRows, patchAt, visit);
            !visited)
            return visited;
        for (std::size_t i = 0; i < count; ++i) {
            PatchInfo& info = records[i].info;
            const PatchId& id = records[i].id;
            float error = std::max(info.error, roundUpToFloat(m_distances[i]));
            for (std::int64_t cy = 2 * id.y;
                 !finest && cy < std::min(2 * id.y + 2, m_childError.endY()); ++cy)
                for (std::int64_t cx = 2 * id.x; cx < std::min(2 * id.x + 2, m_childError.endX());
                     ++cx)
                    error = std::max(error, m_childError.at(cx, cy));
            info.error = error;
            m_error.at(id.x, id.y) = error;
        }
        return {};
    }

    static float roundUpSum(float a, float b) {
        const double exact = double(a) + double(b);
        auto sum = static_cast<float>(exact);
        if (double(sum) < exact) sum = std::nextafter(sum, std::numeric_limits<float>::infinity());
        return sum;
    }

    // The band's even samples that `coarser` takes, row by row.
    Status writeCoarserRows(Band& band, EvenRows& coarser) {
        std::vector<float>& heights = m_rowScratch;
        std::vector<std::uint8_t>& valid = m_validScratch;
        heights.resize(static_cast<std::size_t>(coarser.width()));
        valid.resize(heights.size());
        for (std::int64_t r = std::max<std::int64_t>(band.firstRow, 0);
             r < band.firstRow + band.rows; ++r) {
            const std::int64_t coarseRow = r / 2;
            if (r % 2 != 0 || coarseRow != coarser.originY() + coarser.rowsWritten() ||
                coarser.rowsWritten() >= coarser.height())
                continue;
            const float* h = band.heightRow(r) - band.firstColumn;  // indexed by column
            const std::uint8_t* v = band.validRow(r) - band.firstColumn;
            for (std::int64_t i = 0; i < coarser.width(); ++i) {
                const std::int64_t column = 2 * (coarser.originX() + i);
                heights[static_cast<std::size_t>(i)] = h[column];
                valid[static_cast<std::size_t>(i)] = v[column];
            }
            if (auto ok = coarser.appendRow(heights.data(), valid.data()); !ok) return ok;
        }
        return {};
    }

    // The writer's options for the shards of `level`: a lossy pyramid's codes count in the
    // level's quantizer step.
    ShardWriterOptions shardOptionsOf(int level) const {
        ShardWriterOptions options = m_shardOptions;
        if (m_quantization)
            options.units.quantizerStep = m_quantization->step(level, m_layout.finestLevel());
        return options;
    }

    Status writeRecords(int level, std::vector<PatchRecord>& records, std::int64_t count,
                        std::map<std::pair<std::int64_t, std::int64_t>, ShardWriter>& writers) {
        for (std::int64_t i = 0; i < count; ++i) {
            PatchRecord& record = records[static_cast<std::size_t>(i)];
            const ShardId shard = m_layout.shardOf(record.id);
            auto it = writers.find({shard.y, shard.x});
            if (it == writers.end()) {
                const std::filesystem::path path = m_folder / m_layout.shardPath(shard);
                std::error_code ec;
                std::filesystem::create_directories(path.parent_path(), ec);
                if (ec)
                    return Error{path.parent_path().string() +
                                 ": cannot create folder: " + ec.message()};
                auto writer =
                    ShardWriter::create(path, m_layout, shard, m_withMask, shardOptionsOf(level));
                if (!writer) return writer.error();
                it = writers.emplace(std::pair{shard.y, shard.x}, std::move(writer).value()).first;
            }
            if (auto written = it->second.writeEncoded(m_encoded[static_cast<std::size_t>(i)]);
                !written)
                return written;
            float& levelMax = m_levelMaxError[static_cast<std::size_t>(level)];
            levelMax = std::max(levelMax, record.info.error);
            ++m_patches;
        }
        return {};
    }

    DemReader& m_reader;
    SourceVoids& m_voids;
    DemReader* m_original;  // a resampled source's own samples, else null
    const PyramidLayout& m_layout;
    const PyramidBuildOptions& m_options;
    std::filesystem::path m_folder;
    bool m_withMask;
    unsigned m_threads;
    ShardWriterOptions m_shardOptions;
    DemEdges m_edges;
    DemStatistics m_statistics;
    ChildBounds m_bounds, m_children;  // this pass's patches, and the finer level's
    LevelGrid m_error, m_childError;   // Err(P) of a resampled source's levels
    std::vector<double> m_distances;
    std::int64_t m_originalValid = 0;
    double m_originalFinestDistance = 0.0;
    std::optional<ManifestQuantization> m_quantization;  // a lossy build's
    std::vector<double> m_quantized;                     // per patch of the band
    std::vector<std::vector<float>> m_parentSamples;     // per patch of the band
    std::vector<EncodedPatch> m_encoded;                 // per patch of the band, to write
    std::vector<float> m_rowScratch;
    std::vector<std::uint8_t> m_validScratch;
    std::vector<float> m_levelMaxError;
    std::int64_t m_patches = 0;
    PyramidBuildPhases m_phases;
    double m_totalSamples = 0.0, m_doneSamples = 0.0;
};

}  // namespace terrain::io::detail
