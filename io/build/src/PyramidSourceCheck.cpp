#include "terrain/build/PyramidSourceCheck.h"

#include "GlobeSourceCheck.h"
#include "OriginalSampleDistances.h"
#include "ParallelFor.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <mutex>

namespace terrain::io {
namespace {

// One level's view of the source: the row of patches that covers the current DEM rows.
// A sample on the edge shared by two patches is checked against one of them: both draw
// that edge as the same line (shared samples, no diagonal), so the distance is the same.
class LevelChecker {
public:
    LevelChecker(PyramidReader reader, int level) : m_reader(std::move(reader)), m_level(level) {
        const PyramidLayout& layout = m_reader.layout();
        m_records.resize(static_cast<std::size_t>(layout.patchesX(level)));
    }

    Status checkRows(std::int64_t firstRow, std::int64_t rows, std::int64_t width,
                     const std::vector<float>& samples, SourceCheckReport& report,
                     std::mutex& reportMutex) {
        const PyramidLayout& layout = m_reader.layout();
        const std::int64_t s = layout.levelStep(m_level), q = layout.patchQuads();
        const int t = layout.tileSamples();
        std::int64_t checked = 0;
        for (std::int64_t y = firstRow; y < firstRow + rows; ++y) {
            const std::int64_t py = std::min(y / (q * s), layout.patchesY(m_level) - 1);
            if (py != m_loadedRow) {
                for (std::int64_t px = 0; px < layout.patchesX(m_level); ++px)
                    if (auto read = m_reader.readPatch({m_level, px, py},
                                                       m_records[static_cast<std::size_t>(px)]);
                        !read)
                        return read;
                m_loadedRow = py;
            }
            const double v = double(y - py * q * s) / double(s);
            const float* row = samples.data() + (y - firstRow) * width;
            for (std::int64_t x = 0; x < width; ++x) {
                if (std::isnan(row[x])) continue;
                const std::int64_t px = std::min(x / (q * s), layout.patchesX(m_level) - 1);
                const PatchRecord& patch = m_records[static_cast<std::size_t>(px)];
                const double u = double(x - px * q * s) / double(s);
                if (x % s == 0 && y % s == 0)
                    checkStored(patch, t, u, v, x, y, row[x], report, reportMutex);
                const double distance =
                    detail::distanceToPatchSurface(patch, t, static_cast<int>(q), u, v, row[x]);
                const float bound = patch.info.error;
                ++checked;
                if (bound > 0.0f) m_tightest = std::max(m_tightest, distance / bound);
                if (distance > double(bound)) {
                    std::lock_guard lock(reportMutex);
                    ++report.violationCount;
                    if (report.violations.size() < SourceCheckReport::kMaxListed)
                        report.violations.push_back({patch.id, x, y, distance, bound});
                }
            }
        }
        std::lock_guard lock(reportMutex);
        report.samplesChecked += checked;
        report.storedSamplesChecked += m_storedChecked;
        m_storedChecked = 0;
        return {};
    }

    double tightest() const { return m_tightest; }
    double largestStoredDifference() const { return m_largestStored; }

private:
    // The level's own sample (u, v) of the patch is the source's (x, y) after the lossless
    // or lossy storage (Yusov §4: |ĥ − h| ≤ δ_l); δ is the patch's quantError.
    void checkStored(const PatchRecord& patch, int t, double u, double v, std::int64_t x,
                     std::int64_t y, float source, SourceCheckReport& report,
                     std::mutex& reportMutex) {
        const auto at =
            static_cast<std::size_t>((static_cast<int>(v) + 1) * t + static_cast<int>(u) + 1);
        const double difference = std::abs(double(patch.heights[at]) - double(source));
        ++m_storedChecked;
        m_largestStored = std::max(m_largestStored, difference);
        if (difference <= double(patch.info.quantError)) return;
        std::lock_guard lock(reportMutex);
        ++report.storedViolationCount;
        if (report.violations.size() < SourceCheckReport::kMaxListed)
            report.violations.push_back(
                {patch.id, x, y, difference, patch.info.quantError, /*stored=*/true});
    }

    PyramidReader m_reader;  // one reader per level: readers are single-threaded
    int m_level;
    std::vector<PatchRecord> m_records;
    std::int64_t m_loadedRow = -1;
    double m_tightest = 0.0;
    std::int64_t m_storedChecked = 0;
    double m_largestStored = 0.0;
};

// A resampled source (DemInfo::resampledFrom): its own samples, wherever they lie between
// the pyramid's, level by level and patch row by patch row.
Result<SourceCheckReport> checkOriginalSamples(PyramidReader& reader, DemReader& original,
                                               const ResampledGrid& grid,
                                               const std::function<void(double)>& progress) {
    const PyramidLayout& layout = reader.layout();
    SourceCheckReport report;
    std::vector<PatchRecord> records;
    double rowsDone = 0.0, rowsTotal = 0.0;
    for (int level = 0; level < layout.levelCount(); ++level)
        rowsTotal += double(layout.patchesY(level));
    for (int level = 0; level < layout.levelCount(); ++level) {
        const std::int64_t patchesX = layout.patchesX(level);
        records.resize(static_cast<std::size_t>(patchesX));
        double tightest = 0.0;
        for (std::int64_t py = 0; py < layout.patchesY(level); ++py) {
            for (std::int64_t px = 0; px < patchesX; ++px)
                if (auto read =
                        reader.readPatch({level, px, py}, records[static_cast<std::size_t>(px)]);
                    !read)
                    return read.error();
            const auto patchAt = [&](std::int64_t x, std::int64_t) -> const PatchRecord& {
                return records[static_cast<std::size_t>(x)];
            };
            const auto visit = [&](const PatchRecord& patch, std::int64_t column, std::int64_t row,
                                   double distance) {
                const float bound = patch.info.error;
                ++report.samplesChecked;
                if (bound > 0.0f) tightest = std::max(tightest, distance / bound);
                if (distance <= double(bound)) return;
                ++report.violationCount;
                if (report.violations.size() < SourceCheckReport::kMaxListed)
                    report.violations.push_back({patch.id, column, row, distance, bound});
            };
            if (Status visited = detail::visitOriginalSamples(original, grid, layout, level, py, 1,
                                                              patchAt, visit);
                !visited)
                return visited.error();
            if (progress) progress(++rowsDone / rowsTotal);
        }
        report.tightestRatio.push_back(tightest);
    }
    return report;
}

}  // namespace

Result<SourceCheckReport> checkErrorBoundsAgainstSource(
    const std::filesystem::path& pyramidDir, DemReader& source,
    const std::function<void(double fraction)>& progress) {
    auto first = PyramidReader::open(pyramidDir);
    if (!first) return first.error();
    if (first.value().manifest().globe) {
        DemReader* const sources[] = {&source};
        return checkGlobeErrorBoundsAgainstSources(first.value(), sources, progress);
    }
    const PyramidLayout layout = first.value().layout();
    const DemInfo& dem = source.info();
    if (dem.width != layout.rasterWidth() || dem.height != layout.rasterHeight())
        return Error{fmt::format("{}: {}×{} samples, but the pyramid {} was built from {}×{}",
                                 dem.path, dem.width, dem.height, pyramidDir.string(),
                                 layout.rasterWidth(), layout.rasterHeight())};
    if (DemReader* original = source.originalSamples(); original != nullptr && dem.resampledFrom)
        return checkOriginalSamples(first.value(), *original, *dem.resampledFrom, progress);
    std::vector<LevelChecker> levels;
    for (int level = 0; level < layout.levelCount(); ++level) {
        auto reader = level == 0 ? std::move(first) : PyramidReader::open(pyramidDir);
        if (!reader) return reader.error();
        levels.emplace_back(std::move(reader).value(), level);
    }

    SourceCheckReport report;
    std::mutex reportMutex;
    constexpr std::int64_t kRowsPerRead = 64;
    std::vector<float> samples;
    for (std::int64_t y = 0; y < dem.height; y += kRowsPerRead) {
        const std::int64_t rows = std::min(kRowsPerRead, dem.height - y);
        samples.resize(static_cast<std::size_t>(rows * dem.width));
        if (auto read = source.readWindow(0, y, dem.width, rows, samples); !read)
            return read.error();
        std::vector<Status> results(levels.size());
        parallelFor(static_cast<std::int64_t>(levels.size()), 2, [&](std::int64_t l) {
            results[static_cast<std::size_t>(l)] = levels[static_cast<std::size_t>(l)].checkRows(
                y, rows, dem.width, samples, report, reportMutex);
        });
        for (const Status& result : results)
            if (!result) return result.error();
        if (progress) progress(double(y + rows) / double(dem.height));
    }
    for (const LevelChecker& level : levels) {
        report.tightestRatio.push_back(level.tightest());
        report.largestStoredDifference.push_back(level.largestStoredDifference());
    }
    return report;
}

Result<SourceCheckReport> checkErrorBoundsAgainstSources(
    const std::filesystem::path& pyramidDir, std::span<DemReader* const> sources,
    const std::function<void(double fraction)>& progress) {
    auto reader = PyramidReader::open(pyramidDir);
    if (!reader) return reader.error();
    if (!reader.value().manifest().globe) {
        if (sources.size() != 1)
            return Error{pyramidDir.string() +
                         ": a planar pyramid has one source (a mosaic is one)"};
        return checkErrorBoundsAgainstSource(pyramidDir, *sources.front(), progress);
    }
    return checkGlobeErrorBoundsAgainstSources(reader.value(), sources, progress);
}

}  // namespace terrain::io
