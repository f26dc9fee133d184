// The streaming pyramid build. One pass per level, finest first; each pass walks the
// level in bands of two patch rows (plus the one-sample apron) and
//  - writes the band's patches (heights, mask, λ(d), summary) to their shards,
//  - computes Err_Int of the parent patches, whose four children the band holds,
//  - writes the band's even samples into the next coarser level's raster (a temporary
//    file): h^(l−1)_{i,j} ≡ h^(l)_{2i,2j} (Yusov & Shevtsov 2011, §4).
// Err_Appr(P) = Err_Int(P) + max over children Err_Appr (§4, nested like ROAM's wedgies)
// is then known when the coarser level's pass reaches P.
#include "terrain/io/PyramidBuilder.h"

#include "BuildClock.h"
#include "BuildOutput.h"
#include "OriginalSampleDistances.h"
#include "ParallelFor.h"
#include "SourceCoverage.h"
#include "terrain/base/Assert.h"
#include "terrain/io/HeightCodes.h"
#include "terrain/io/NoDataFill.h"
#include "terrain/io/PatchErrors.h"
#include "terrain/io/PatchRecord.h"
#include "terrain/io/ShardWriter.h"

#include <fmt/core.h>

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

namespace terrain::io {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Rows [firstRow, firstRow + rows) of one level's padded raster, columns −1 … samplesX
// (the apron on both sides) stored from index 0.
struct Band {
    std::int64_t firstRow = 0;
    std::int64_t rows = 0;
    std::int64_t width = 0;  // samplesX + 2
    std::vector<float> heights;
    std::vector<std::uint8_t> valid;

    float* heightRow(std::int64_t row) { return heights.data() + (row - firstRow) * width; }
    std::uint8_t* validRow(std::int64_t row) { return valid.data() + (row - firstRow) * width; }
};

// What the finest pass learns about the DEM for the coarser passes and the manifest.
struct DemEdges {
    std::vector<float> lastColumn;  // filled value at x = W − 1, for every row
    std::vector<float> lastRow;     // filled row y = H − 1
};

struct DemStatistics {
    double minHeight = std::numeric_limits<double>::infinity();
    double maxHeight = -std::numeric_limits<double>::infinity();
    std::int64_t validSamples = 0;
    std::int64_t noDataSamples = 0;
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
    FinestRows(DemReader& reader, std::int64_t samplesX, DemEdges& edges, DemStatistics& stats)
        : m_reader(reader),
          m_w(reader.info().width),
          m_h(reader.info().height),
          m_samplesX(samplesX),
          m_edges(edges),
          m_stats(stats),
          m_fillUnits(wholeSourceUnits(reader.info())) {
        m_edges.lastColumn.assign(static_cast<std::size_t>(m_h), 0.0f);
    }

    Status fetch(Band& band) override {
        const std::int64_t first = std::max<std::int64_t>(band.firstRow, 0);
        const std::int64_t last = std::min(band.firstRow + band.rows, m_h);  // exclusive
        if (last > first) {
            m_scratch.resize(static_cast<std::size_t>((last - first) * m_w));
            if (auto read = m_reader.readWindow(0, first, m_w, last - first, m_scratch); !read)
                return read;
        }
        for (std::int64_t r = band.firstRow; r < band.firstRow + band.rows; ++r) {
            float* out = band.heightRow(r);
            std::uint8_t* valid = band.validRow(r);
            if (r >= 0 && r < m_h) {
                std::span<float> row(out + 1, static_cast<std::size_t>(m_w));
                std::copy_n(m_scratch.data() + (r - first) * m_w, m_w, row.data());
                const std::int64_t filled =
                    fillNoDataRow(row, std::span<std::uint8_t>(valid + 1, row.size()), m_fillUnits);
                if (r >= m_nextStatisticsRow) {  // bands overlap by their apron rows
                    countStatistics(row, valid + 1, filled);
                    m_edges.lastColumn[static_cast<std::size_t>(r)] = row.back();
                    m_nextStatisticsRow = r + 1;
                }
                padRow(out, valid);
                if (r == m_h - 1) m_lastRow.assign(out, out + band.width);
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
        if (m_edges.lastRow.empty() && !m_lastRow.empty())
            m_edges.lastRow.assign(m_lastRow.begin() + 1, m_lastRow.begin() + 1 + m_w);
        return {};
    }

private:
    // Columns beyond the DEM copy x = W − 1; the west apron copies x = 0.
    void padRow(float* out, std::uint8_t* valid) const {
        out[0] = out[1];
        valid[0] = 0;
        for (std::int64_t x = m_w + 1; x < m_samplesX + 2; ++x) {
            out[x] = out[m_w];
            valid[x] = 0;
        }
    }

    void countStatistics(std::span<const float> row, const std::uint8_t* valid,
                         std::int64_t filled) {
        for (std::size_t i = 0; i < row.size(); ++i) {
            if (!valid[i]) continue;
            m_stats.minHeight = std::min(m_stats.minHeight, double(row[i]));
            m_stats.maxHeight = std::max(m_stats.maxHeight, double(row[i]));
        }
        m_stats.validSamples += static_cast<std::int64_t>(row.size()) - filled;
        m_stats.noDataSamples += filled;
    }

    DemReader& m_reader;
    std::int64_t m_w, m_h, m_samplesX;
    DemEdges& m_edges;
    DemStatistics& m_stats;
    std::optional<VerticalTransform> m_fillUnits;  // the fill's rounding (NoDataFill.h)
    std::vector<float> m_scratch;
    std::vector<float> m_lastRow;  // padded row H − 1 (with apron)
    std::int64_t m_nextStatisticsRow = 0;
};

// A level's samples that lie on the DEM ("inside": i·step ≤ W − 1, j·step ≤ H − 1), as a
// temporary file of float32 rows plus one of mask bytes, written by the finer level's
// pass and read back band by band.
class InsideRaster {
public:
    static Result<InsideRaster> create(const fs::path& path, std::int64_t width,
                                       std::int64_t height) {
        InsideRaster r;
        r.m_path = path;
        r.m_width = width;
        r.m_height = height;
        r.m_heights = std::fopen(path.c_str(), "w+b");
        r.m_valid = std::fopen((path.string() + ".valid").c_str(), "w+b");
        if (r.m_heights == nullptr || r.m_valid == nullptr)
            return Error{path.string() + ": cannot create temporary level raster: " +
                         std::generic_category().message(errno)};
        return r;
    }
    InsideRaster() = default;
    InsideRaster(InsideRaster&& o) noexcept { *this = std::move(o); }
    InsideRaster& operator=(InsideRaster&& o) noexcept {
        std::swap(m_path, o.m_path);
        std::swap(m_width, o.m_width);
        std::swap(m_height, o.m_height);
        std::swap(m_heights, o.m_heights);
        std::swap(m_valid, o.m_valid);
        std::swap(m_rowsWritten, o.m_rowsWritten);
        return *this;
    }
    ~InsideRaster() {
        if (m_heights != nullptr) std::fclose(m_heights);
        if (m_valid != nullptr) std::fclose(m_valid);
        std::error_code ec;
        if (!m_path.empty()) {
            fs::remove(m_path, ec);
            fs::remove(m_path.string() + ".valid", ec);
        }
    }

    std::int64_t width() const { return m_width; }
    std::int64_t height() const { return m_height; }
    std::int64_t rowsWritten() const { return m_rowsWritten; }

    Status appendRow(const float* heights, const std::uint8_t* valid) {
        const auto n = static_cast<std::size_t>(m_width);
        if (std::fwrite(heights, sizeof(float), n, m_heights) != n ||
            std::fwrite(valid, 1, n, m_valid) != n)
            return Error{m_path.string() + ": cannot write temporary level raster: " +
                         std::generic_category().message(errno)};
        ++m_rowsWritten;
        return {};
    }

    Status readRow(std::int64_t row, float* heights, std::uint8_t* valid) const {
        const auto n = static_cast<std::size_t>(m_width);
        const auto fdHeights = fileno(m_heights), fdValid = fileno(m_valid);
        const auto bytes = static_cast<ssize_t>(n * sizeof(float));
        if (pread(fdHeights, heights, n * sizeof(float), row * bytes) != bytes ||
            pread(fdValid, valid, n, row * static_cast<off_t>(n)) != static_cast<ssize_t>(n))
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
    fs::path m_path;
    std::int64_t m_width = 0, m_height = 0;
    std::FILE* m_heights = nullptr;
    std::FILE* m_valid = nullptr;
    std::int64_t m_rowsWritten = 0;
};

class CoarseRows final : public LevelRows {
public:
    CoarseRows(const InsideRaster& inside, const DemEdges& edges, std::int64_t step,
               std::int64_t demWidth, std::int64_t samplesX)
        : m_inside(inside),
          m_edges(edges),
          m_step(step),
          m_demWidth(demWidth),
          m_samplesX(samplesX) {}

    Status fetch(Band& band) override {
        for (std::int64_t r = band.firstRow; r < band.firstRow + band.rows; ++r) {
            float* out = band.heightRow(r);
            std::uint8_t* valid = band.validRow(r);
            const std::int64_t row = std::max<std::int64_t>(r, 0);  // apron row −1 → row 0
            if (row < m_inside.height()) {
                if (auto read = m_inside.readRow(row, out + 1, valid + 1); !read) return read;
                const float edge = m_edges.lastColumn[static_cast<std::size_t>(row * m_step)];
                for (std::int64_t i = m_inside.width(); i < m_samplesX + 1; ++i) {
                    out[i + 1] = edge;
                    valid[i + 1] = 0;
                }
            } else {
                for (std::int64_t i = 0; i < m_samplesX + 1; ++i) {
                    const std::int64_t x = std::min(i * m_step, m_demWidth - 1);
                    out[i + 1] = m_edges.lastRow[static_cast<std::size_t>(x)];
                    valid[i + 1] = 0;
                }
            }
            out[0] = out[1];
            valid[0] = 0;
            if (r < 0) std::fill_n(valid, band.width, std::uint8_t{0});
        }
        return {};
    }

private:
    const InsideRaster& m_inside;
    const DemEdges& m_edges;
    std::int64_t m_step, m_demWidth, m_samplesX;
};

// Patch-indexed grid of floats for one level.
struct LevelGrid {
    std::int64_t width = 0, height = 0;
    std::vector<float> values;
    void reset(std::int64_t w, std::int64_t h) {
        width = w;
        height = h;
        values.assign(static_cast<std::size_t>(w * h), 0.0f);
    }
    float& at(std::int64_t x, std::int64_t y) {
        return values[static_cast<std::size_t>(y * width + x)];
    }
    float at(std::int64_t x, std::int64_t y) const {
        return values[static_cast<std::size_t>(y * width + x)];
    }
};

class Builder {
public:
    Builder(DemReader& reader, const PyramidLayout& layout, const PyramidBuildOptions& options,
            const fs::path& folder, bool withMask)
        : m_reader(reader),
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

    Status run() {
        const int finest = m_layout.finestLevel();
        std::optional<InsideRaster> inside;  // the current level's raster (coarse levels)
        for (int level = finest; level >= 0; --level) {
            std::optional<InsideRaster> coarser;
            if (level > 0) {
                const std::int64_t step = m_layout.levelStep(level - 1);
                auto made =
                    InsideRaster::create(m_folder / "tmp" / fmt::format("level-{}.raw", level - 1),
                                         (m_reader.info().width - 1) / step + 1,
                                         (m_reader.info().height - 1) / step + 1);
                if (!made) return made.error();
                coarser.emplace(std::move(made).value());
            }
            std::unique_ptr<LevelRows> rows;
            if (level == finest)
                rows = std::make_unique<FinestRows>(m_reader, m_layout.levelSamplesX(level),
                                                    m_edges, m_statistics);
            else
                rows = std::make_unique<CoarseRows>(*inside, m_edges, m_layout.levelStep(level),
                                                    m_reader.info().width,
                                                    m_layout.levelSamplesX(level));
            if (auto pass = runLevel(level, *rows, coarser ? &*coarser : nullptr); !pass)
                return pass;
            rows.reset();
            inside = std::move(coarser);
        }
        return {};
    }

    const DemStatistics& statistics() const { return m_statistics; }
    std::int64_t patches() const { return m_patches; }
    float rootError() const { return m_rootError; }
    const std::vector<float>& levelMaxError() const { return m_levelMaxError; }
    /// A resampled source's own valid samples, and their largest distance from the finest
    /// level's surface.
    std::int64_t originalValidSamples() const { return m_originalValid; }
    double originalFinestDistance() const { return m_originalFinestDistance; }
    /// Set for a lossy build, with the largest difference the finest level's quantizer made.
    const std::optional<ManifestQuantization>& quantization() const { return m_quantization; }
    const PyramidBuildPhases& phases() const { return m_phases; }

private:
    Status runLevel(int level, LevelRows& rows, InsideRaster* coarser) {
        const int q = m_layout.patchQuads();
        const std::int64_t patchesX = m_layout.patchesX(level), patchesY = m_layout.patchesY(level);
        const std::int64_t samplesX = m_layout.levelSamplesX(level);

        // Err_Appr(P) = Err_Int(P) + max over children (0 at the finest level).
        m_approx.reset(patchesX, patchesY);
        if (m_original != nullptr) m_error.reset(patchesX, patchesY);
        LevelGrid parentInterpolation;
        if (level > 0)
            parentInterpolation.reset(m_layout.patchesX(level - 1), m_layout.patchesY(level - 1));

        Band band;
        band.width = samplesX + 2;
        band.heights.resize(static_cast<std::size_t>((2 * q + 3) * band.width));
        band.valid.resize(band.heights.size());
        std::vector<PatchRecord> records(static_cast<std::size_t>(2 * patchesX));
        std::map<std::pair<std::int64_t, std::int64_t>, ShardWriter> writers;  // by (row, column)

        for (std::int64_t pairRow = 0; pairRow * 2 < patchesY; ++pairRow) {
            if (m_options.cancel != nullptr && m_options.cancel->load())
                return Error{m_folder.string() + ": build interrupted"};
            const std::int64_t firstPatchRow = pairRow * 2;
            const int patchRows =
                static_cast<int>(std::min<std::int64_t>(2, patchesY - firstPatchRow));
            band.firstRow = firstPatchRow * q - 1;
            band.rows = patchRows * q + 3;
            auto phaseStart = Clock::now();
            if (auto fetched = rows.fetch(band); !fetched) return fetched;
            m_phases.readSeconds += secondsSince(phaseStart);
            phaseStart = Clock::now();

            // Patches of the band, in parallel.
            const std::int64_t count = patchRows * patchesX;
            m_quantized.assign(static_cast<std::size_t>(count), 0.0);
            m_parentSamples.resize(static_cast<std::size_t>(count));
            parallelFor(count, m_threads, [&](std::int64_t i) {
                m_quantized[static_cast<std::size_t>(i)] = makeRecord(
                    level, band, PatchId{level, i % patchesX, firstPatchRow + i / patchesX},
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
            // Err_Int of the parents whose children are in this band (Yusov §4).
            if (level > 0) {
                parallelFor(m_layout.patchesX(level - 1), m_threads, [&](std::int64_t parentX) {
                    const int childrenX =
                        static_cast<int>(std::min<std::int64_t>(2, patchesX - 2 * parentX));
                    const GridView children{band.heightRow(firstPatchRow * q) + 1 + 2 * parentX * q,
                                            2 * q + 1, band.width};
                    parentInterpolation.at(parentX, pairRow) =
                        simplificationError(children, 0, 0, childrenX * q, patchRows * q, 2);
                });
                if (auto written = writeCoarserRows(band, *coarser); !written) return written;
            }
            m_phases.boundsSeconds += secondsSince(phaseStart);
            phaseStart = Clock::now();
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
            m_doneSamples += double(patchRows * q) * double(samplesX);
            if (m_options.progress)
                m_options.progress({level, std::min(1.0, m_doneSamples / m_totalSamples)});
        }
        if (coarser != nullptr) {
            if (auto flushed = coarser->flush(); !flushed) return flushed;
            TERRAIN_ASSERT(coarser->rowsWritten() == coarser->height());
        }
        m_childApprox = m_approx;
        m_childError = m_error;
        m_interpolation = std::move(parentInterpolation);
        if (level == 0) m_rootError = m_levelMaxError[0];  // the one root patch's Err(P)
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
        const std::int64_t x0 = id.x * q;  // band column of the apron = level x − 1 + 1
        for (int j = 0; j < t; ++j) {
            const std::int64_t row = id.y * q - 1 + j;
            std::copy_n(band.heightRow(row) + x0, t, record.heights.data() + j * t);
            std::copy_n(band.validRow(row) + x0, t, record.valid.data() + j * t);
        }
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

        float approx = 0.0f;
        if (level < m_layout.finestLevel()) {
            float worstChild = 0.0f;
            for (std::int64_t cy = 2 * id.y; cy < std::min(2 * id.y + 2, m_childApprox.height);
                 ++cy)
                for (std::int64_t cx = 2 * id.x; cx < std::min(2 * id.x + 2, m_childApprox.width);
                     ++cx)
                    worstChild = std::max(worstChild, m_childApprox.at(cx, cy));
            approx = roundUpSum(m_interpolation.at(id.x, id.y), worstChild);
        }
        m_approx.at(id.x, id.y) = approx;
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
    // stays Yusov's: the bound against the resampled grid.
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
                 !finest && cy < std::min(2 * id.y + 2, m_childError.height); ++cy)
                for (std::int64_t cx = 2 * id.x; cx < std::min(2 * id.x + 2, m_childError.width);
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

    Status writeCoarserRows(Band& band, InsideRaster& coarser) {
        std::vector<float>& heights = m_rowScratch;
        std::vector<std::uint8_t>& valid = m_validScratch;
        heights.resize(static_cast<std::size_t>(coarser.width()));
        valid.resize(heights.size());
        for (std::int64_t r = std::max<std::int64_t>(band.firstRow, 0);
             r < band.firstRow + band.rows; ++r) {
            if (r % 2 != 0 || r / 2 != coarser.rowsWritten() || r / 2 >= coarser.height()) continue;
            const float* h = band.heightRow(r) + 1;
            const std::uint8_t* v = band.validRow(r) + 1;
            for (std::int64_t i = 0; i < coarser.width(); ++i) {
                heights[static_cast<std::size_t>(i)] = h[2 * i];
                valid[static_cast<std::size_t>(i)] = v[2 * i];
            }
            if (auto ok = coarser.appendRow(heights.data(), valid.data()); !ok) return ok;
        }
        return {};
    }

    Status writeRecords(int level, std::vector<PatchRecord>& records, std::int64_t count,
                        std::map<std::pair<std::int64_t, std::int64_t>, ShardWriter>& writers) {
        for (std::int64_t i = 0; i < count; ++i) {
            PatchRecord& record = records[static_cast<std::size_t>(i)];
            const ShardId shard = m_layout.shardOf(record.id);
            auto it = writers.find({shard.y, shard.x});
            if (it == writers.end()) {
                const fs::path path = m_folder / m_layout.shardPath(shard);
                std::error_code ec;
                fs::create_directories(path.parent_path(), ec);
                if (ec)
                    return Error{path.parent_path().string() +
                                 ": cannot create folder: " + ec.message()};
                ShardWriterOptions options = m_shardOptions;
                if (m_quantization)
                    options.units.quantizerStep =
                        m_quantization->step(level, m_layout.finestLevel());
                auto writer = ShardWriter::create(path, m_layout, shard, m_withMask, options);
                if (!writer) return writer.error();
                it = writers.emplace(std::pair{shard.y, shard.x}, std::move(writer).value()).first;
            }
            if (auto written =
                    it->second.writePatch(record, m_parentSamples[static_cast<std::size_t>(i)]);
                !written)
                return written;
            float& levelMax = m_levelMaxError[static_cast<std::size_t>(level)];
            levelMax = std::max(levelMax, record.info.error);
            ++m_patches;
        }
        return {};
    }

    DemReader& m_reader;
    DemReader* m_original;  // a resampled source's own samples, else null
    const PyramidLayout& m_layout;
    const PyramidBuildOptions& m_options;
    fs::path m_folder;
    bool m_withMask;
    unsigned m_threads;
    ShardWriterOptions m_shardOptions;
    DemEdges m_edges;
    DemStatistics m_statistics;
    LevelGrid m_approx, m_childApprox, m_interpolation;
    LevelGrid m_error, m_childError;  // Err(P) of a resampled source's levels
    std::vector<double> m_distances;
    std::int64_t m_originalValid = 0;
    double m_originalFinestDistance = 0.0;
    std::optional<ManifestQuantization> m_quantization;  // a lossy build's
    std::vector<double> m_quantized;                     // per patch of the band
    std::vector<std::vector<float>> m_parentSamples;     // per patch of the band
    std::vector<float> m_rowScratch;
    std::vector<std::uint8_t> m_validScratch;
    std::vector<float> m_levelMaxError;
    std::int64_t m_patches = 0;
    float m_rootError = 0.0f;
    PyramidBuildPhases m_phases;
    double m_totalSamples = 0.0, m_doneSamples = 0.0;
};

}  // namespace
}  // namespace terrain::io

namespace terrain::io {
namespace {

PyramidManifest makeManifest(const DemReader& reader, const PyramidLayout& layout,
                             const Builder& builder, bool withMask) {
    const DemInfo& dem = reader.info();
    const DemStatistics& stats = builder.statistics();
    PyramidManifest m = PyramidManifest::forLayout(layout);
    m.georeference = dem.georeference;
    m.vertical = dem.vertical;
    m.noData.present = withMask;
    m.noData.sourceValue = dem.noDataValue;
    m.noData.samples = stats.noDataSamples;
    m.statistics.minHeight = stats.validSamples > 0 ? stats.minHeight : 0.0;
    m.statistics.maxHeight = stats.validSamples > 0 ? stats.maxHeight : 0.0;
    m.statistics.validSamples = stats.validSamples;
    m.statistics.rootError = builder.rootError();
    for (ManifestLevel& level : m.levels)
        level.maxError = builder.levelMaxError()[static_cast<std::size_t>(level.level)];
    m.source.inputs = dem.inputs;
    m.source.reader = dem.readerName;
    m.source.sampleType = dem.sampleType;
    m.source.band = dem.band;
    m.source.bandCount = dem.bandCount;
    m.source.rowsFlipped = dem.rowsFlipped;
    m.source.columnsFlipped = dem.columnsFlipped;
    if (dem.resampledFrom)
        m.source.resampled =
            ManifestResampling{dem.resampledFrom->method,      dem.resampledFrom->width,
                               dem.resampledFrom->height,      dem.resampledFrom->geoTransform,
                               builder.originalValidSamples(), builder.originalFinestDistance()};
    m.quantization = builder.quantization();
    m.build.tool = "terrain-build";
    m.build.version = TERRAIN_VERSION;
    return m;
}

}  // namespace

Result<PyramidBuildSummary> buildPyramid(DemReader& reader, const fs::path& output,
                                         const PyramidBuildOptions& options) {
    const auto start = Clock::now();
    const DemInfo& dem = reader.info();
    if (Status delta = checkMaxErrorM(output, options.maxErrorM); !delta) return delta.error();
    auto layout = PyramidLayout::create(dem.width, dem.height, options.patchSamples,
                                        options.blockQuads, options.shardPatches);
    if (!layout) return Error{dem.path + ": " + layout.error().message};
    const PyramidLayout& l = layout.value();

    // The band of the finest level dominates memory: two patch rows of padded samples
    // (heights and mask), the reader's window, and the patch records.
    const auto bandBytes = std::uint64_t(2 * l.patchQuads() + 3) *
                           std::uint64_t(l.levelSamplesX(l.finestLevel()) + 2) * 5;
    const auto recordBytes = std::uint64_t(2 * l.patchesX(l.finestLevel())) *
                             std::uint64_t(l.tileSamples() * l.tileSamples()) * 5;
    const std::uint64_t neededBytes = 2 * bandBytes + recordBytes + (std::uint64_t{64} << 20);
    if (neededBytes > options.memoryBudgetBytes)
        return Error{fmt::format(
            "{}: {} samples wide: a band of two patch rows needs about {} MiB, more than the "
            "memory budget of {} MiB (raise --memory; builds in column strips are not "
            "implemented yet)",
            dem.path, dem.width, neededBytes >> 20, options.memoryBudgetBytes >> 20)};

    Result<PartialBuildFolder> created = PartialBuildFolder::create(output, options.overwrite);
    if (!created) return created.error();
    PartialBuildFolder& partial = created.value();

    // The mask is stored when the source declares a no-data value. NaN samples of a float
    // source that declares none are filled and counted all the same, but not masked: the
    // mask costs 2 bytes a sample (half) in every tile, and the build streams, so it has to
    // decide before it has seen the samples.
    // A resampled source is masked too: the resampled grid's corners outside it are no-data.
    const bool withMask = dem.noDataValue.has_value() || dem.resampledFrom.has_value();
    Builder builder(reader, l, options, partial.path(), withMask);
    if (auto built = builder.run(); !built) return built.error();

    PyramidBuildSummary summary;
    summary.manifest = makeManifest(reader, l, builder, withMask);
    // Coverage is the source's own: a rotated grid's resampling is partly empty by shape.
    const auto& resampled = summary.manifest.source.resampled;
    const std::int64_t samples =
        resampled ? resampled->width * resampled->height : dem.width * dem.height;
    const std::int64_t valid =
        resampled ? resampled->validSamples : summary.manifest.statistics.validSamples;
    if (Status empty = refuseEmptySource(dem.path, samples, valid); !empty) return empty.error();
    if (auto warning = mostlyNoDataWarning(dem.path, samples, valid))
        summary.warnings.push_back(*warning);
    summary.patches = builder.patches();
    summary.phases = builder.phases();
    summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    summary.manifest.build.seconds = summary.seconds;
    if (auto written = writeManifest(partial.path(), summary.manifest); !written)
        return written.error();
    summary.bytes = folderBytes(partial.path());

    if (Status committed = partial.commit(); !committed) return committed.error();
    return summary;
}

}  // namespace terrain::io
