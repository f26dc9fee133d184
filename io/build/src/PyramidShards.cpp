#include "terrain/build/PyramidShards.h"

#include "BuildBudget.h"
#include "BuildClock.h"
#include "BuildOutput.h"
#include "LevelBuilder.h"
#include "PlanarBuildTotals.h"
#include "RegionStaging.h"
#include "ShardCarry.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <map>
#include <sstream>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;
using detail::ChildBounds;
using detail::PatchRect;

// What decides the shards' bytes: the source as read and the build options.
std::string planarFingerprint(const DemInfo& dem, const PyramidLayout& layout,
                          const PyramidBuildOptions& options) {
    return detail::regionFingerprint(dem, layout, options,
                                     {{"tiling", "planar"},
                                      {"formatVersion", PyramidManifest::kFormatVersion},
                                      {"parentPrediction", options.parentPrediction}});
}

PatchRect patchesOf(const PyramidLayout& layout, const ShardId& s) {
    const std::int64_t x0 = layout.shardFirstX(s), y0 = layout.shardFirstY(s);
    return {x0, y0, x0 + layout.shardCountX(s), y0 + layout.shardCountY(s)};
}

// Samples of `level` on the DEM: i · step ≤ W − 1 (and rows alike).
std::int64_t insideSamples(const PyramidLayout& layout, int level, std::int64_t demSamples) {
    return (demSamples - 1) / layout.levelStep(level) + 1;
}

// The coarser level's samples a shard of `level` owns: the even ones among its own samples
// [first patch's first sample, next shard's first sample), the last shard's to the end.
struct EvenRange {
    std::int64_t x0, y0, x1, y1;
};
EvenRange evenRangeOf(const PyramidLayout& layout, const ShardId& s, std::int64_t w,
                      std::int64_t h) {
    const PatchRect rect = patchesOf(layout, s);
    const int q = layout.patchQuads();
    const std::int64_t insideW = insideSamples(layout, s.level - 1, w);
    const std::int64_t insideH = insideSamples(layout, s.level - 1, h);
    const bool lastX = s.x == layout.shardsX(s.level) - 1,
               lastY = s.y == layout.shardsY(s.level) - 1;
    return {rect.x0 * q / 2, rect.y0 * q / 2, lastX ? insideW : std::min(rect.x1 * q / 2, insideW),
            lastY ? insideH : std::min(rect.y1 * q / 2, insideH)};
}

// The coarser level's even samples of a region, in memory until they go to its carry.
class EvenBlock final : public detail::EvenRows {
public:
    explicit EvenBlock(const EvenRange& r)
        : m_range(r),
          m_heights(static_cast<std::size_t>((r.x1 - r.x0) * (r.y1 - r.y0))),
          m_valid(m_heights.size()) {}
    std::int64_t originX() const override { return m_range.x0; }
    std::int64_t originY() const override { return m_range.y0; }
    std::int64_t width() const override { return m_range.x1 - m_range.x0; }
    std::int64_t height() const override { return m_range.y1 - m_range.y0; }
    std::int64_t rowsWritten() const override { return m_rows; }
    Status appendRow(const float* heights, const std::uint8_t* valid) override {
        const auto at = static_cast<std::size_t>(m_rows * width());
        std::copy_n(heights, width(), m_heights.begin() + static_cast<std::ptrdiff_t>(at));
        std::copy_n(valid, width(), m_valid.begin() + static_cast<std::ptrdiff_t>(at));
        ++m_rows;
        return {};
    }
    void moveTo(detail::ShardCarry& carry) {
        TERRAIN_ASSERT(m_rows == height(), "every even row of the shard was written");
        carry.evenX0 = m_range.x0;
        carry.evenY0 = m_range.y0;
        carry.evenWidth = width();
        carry.evenHeight = height();
        carry.evenHeights = std::move(m_heights);
        carry.evenValid = std::move(m_valid);
    }

private:
    EvenRange m_range;
    std::vector<float> m_heights;
    std::vector<std::uint8_t> m_valid;
    std::int64_t m_rows = 0;
};

Result<detail::ShardCarry> readChildCarry(const fs::path& staging, const ShardId& child,
                                          const std::string& fingerprint, bool whole) {
    const fs::path path = detail::carryPath(staging, child);
    auto carry = detail::readCarry(path, whole);
    if (!carry) return carry.error();
    if (Status origin = detail::checkCarryOrigin(path, fingerprint, carry.value().fingerprint,
                                                 child, carry.value().shard);
        !origin)
        return origin.error();
    return carry;
}

// A coarse region's samples on the DEM, gathered from the carries of the finer shards
// beneath it, and its children's bounds.
class CarriedSamples final : public detail::InsideSamples {
public:
    static Result<std::unique_ptr<CarriedSamples>> load(
        const fs::path& staging, const PyramidLayout& layout, const ShardId& shard, std::int64_t w,
        std::int64_t h, const std::string& fingerprint, ChildBounds& children) {
        auto s = std::unique_ptr<CarriedSamples>(new CarriedSamples);
        const int q = layout.patchQuads();
        const PatchRect rect = patchesOf(layout, shard);
        s->m_width = insideSamples(layout, shard.level, w);
        s->m_height = insideSamples(layout, shard.level, h);
        s->m_x0 = std::max<std::int64_t>(0, rect.x0 * q - 1);
        s->m_y0 = std::max<std::int64_t>(0, rect.y0 * q - 1);
        s->m_x1 = std::min(rect.x1 * q + 2, s->m_width);
        s->m_y1 = std::min(rect.y1 * q + 2, s->m_height);
        const auto samples = static_cast<std::size_t>((s->m_x1 - s->m_x0) * (s->m_y1 - s->m_y0));
        s->m_heights.assign(samples, 0.0f);
        s->m_valid.assign(samples, 0);
        std::vector<std::uint8_t> covered(samples, 0);

        const int finer = shard.level + 1;
        const PatchRect childRect{2 * rect.x0, 2 * rect.y0,
                                  std::min(2 * rect.x1, layout.patchesX(finer)),
                                  std::min(2 * rect.y1, layout.patchesY(finer))};
        children.approx.reset(childRect);
        children.interpolation.reset(childRect);
        for (const ShardId& child : shardInputs(layout, shard)) {
            auto read = readChildCarry(staging, child, fingerprint, true);
            if (!read) return read.error();
            const detail::ShardCarry& c = read.value();
            for (std::int64_t y = std::max(s->m_y0, c.evenY0);
                 y < std::min(s->m_y1, c.evenY0 + c.evenHeight); ++y)
                for (std::int64_t x = std::max(s->m_x0, c.evenX0);
                     x < std::min(s->m_x1, c.evenX0 + c.evenWidth); ++x) {
                    const auto from =
                        static_cast<std::size_t>((y - c.evenY0) * c.evenWidth + (x - c.evenX0));
                    const auto to = s->index(x, y);
                    s->m_heights[to] = c.evenHeights[from];
                    s->m_valid[to] = c.evenValid[from];
                    covered[to] = 1;
                }
            copyBounds(c.bounds.approx, children.approx);
            copyBounds(c.bounds.interpolation, children.interpolation);
        }
        if (std::find(covered.begin(), covered.end(), 0) != covered.end())
            return Error{fmt::format("{}: the carries of level {} do not cover shard {}/{}/{}",
                                     staging.string(), finer, shard.level, shard.x, shard.y)};
        return s;
    }

    std::int64_t width() const override { return m_width; }
    std::int64_t height() const override { return m_height; }
    Status readRow(std::int64_t row, std::int64_t x0, std::int64_t count, float* heights,
                   std::uint8_t* valid) override {
        TERRAIN_ASSERT(row >= m_y0 && row < m_y1 && x0 >= m_x0 && x0 + count <= m_x1,
                       "a coarse band reads within its shard's window");
        std::copy_n(m_heights.begin() + static_cast<std::ptrdiff_t>(index(x0, row)), count,
                    heights);
        std::copy_n(m_valid.begin() + static_cast<std::ptrdiff_t>(index(x0, row)), count, valid);
        return {};
    }

private:
    CarriedSamples() = default;
    std::size_t index(std::int64_t x, std::int64_t y) const {
        return static_cast<std::size_t>((y - m_y0) * (m_x1 - m_x0) + (x - m_x0));
    }
    static void copyBounds(const detail::LevelGrid& from, detail::LevelGrid& to) {
        for (std::int64_t y = std::max(from.y0, to.y0); y < std::min(from.endY(), to.endY()); ++y)
            for (std::int64_t x = std::max(from.x0, to.x0); x < std::min(from.endX(), to.endX());
                 ++x)
                to.at(x, y) = from.at(x, y);
    }

    std::int64_t m_width = 0, m_height = 0;  // the level's inside samples
    std::int64_t m_x0 = 0, m_y0 = 0, m_x1 = 0, m_y1 = 0;
    std::vector<float> m_heights;
    std::vector<std::uint8_t> m_valid;
};

// The DEM's edges, from the files the finest shards on the east and south edges wrote.
class CarriedEdges final : public detail::DemEdgeSamples {
public:
    CarriedEdges(fs::path staging, const PyramidLayout& layout)
        : m_staging(std::move(staging)), m_layout(layout) {}

    Result<float> lastColumn(std::int64_t row) override { return at(true, row); }
    Result<float> lastRow(std::int64_t column) override { return at(false, column); }

private:
    Result<float> at(bool east, std::int64_t sample) {
        const int finest = m_layout.finestLevel();
        const std::int64_t shardSamples =
            std::int64_t{m_layout.shardPatches()} * m_layout.patchQuads();
        const std::int64_t shards = east ? m_layout.shardsY(finest) : m_layout.shardsX(finest);
        const std::int64_t index = std::min(sample / shardSamples, shards - 1);
        auto found = m_runs.find({east, index});
        if (found == m_runs.end()) {
            auto read = detail::readEdge(detail::edgePath(m_staging, east, index));
            if (!read) return read.error();
            found = m_runs.emplace(std::pair{east, index}, std::move(read).value()).first;
        }
        const detail::EdgeRun& run = found->second;
        if (sample < run.first || sample - run.first >= std::ssize(run.values))
            return Error{detail::edgePath(m_staging, east, index).string() +
                         ": does not hold DEM sample " + std::to_string(sample)};
        return run.values[static_cast<std::size_t>(sample - run.first)];
    }

    fs::path m_staging;
    const PyramidLayout& m_layout;
    std::map<std::pair<bool, std::int64_t>, detail::EdgeRun> m_runs;
};

Result<ShardPlan> openPlan(DemReader& reader, const fs::path& output,
                           const PyramidBuildOptions& options, bool create) {
    const DemInfo& dem = reader.info();
    if (Status delta = checkMaxErrorM(output, options.maxErrorM); !delta) return delta.error();
    if (dem.resampledFrom)
        return Error{dem.path +
                     ": a rotated or sheared source is not built shard by shard yet "
                     "(build it whole)"};
    auto layout = PyramidLayout::create(dem.width, dem.height, options.patchSamples,
                                        options.blockQuads, options.shardPatches);
    if (!layout) return Error{dem.path + ": " + layout.error().message};
    ShardPlan plan{layout.value(), shardStagingFolder(output),
                   planarFingerprint(dem, layout.value(), options)};
    if (Status fits = detail::checkMemoryBudget(
            dem.path,
            fmt::format("a shard of {} × {} patches", options.shardPatches, options.shardPatches),
            planarShardBytes(plan.layout), options.memoryBudgetBytes,
            "lower --shard-patches or raise --memory");
        !fits)
        return fits.error();
    if (Status opened = detail::openStagingPlan(plan.staging, plan.fingerprint, create); !opened)
        return opened.error();
    return plan;
}

}  // namespace

fs::path shardStagingFolder(const fs::path& output) {
    fs::path normal = output.lexically_normal();
    if (normal.filename().empty()) normal = normal.parent_path();
    return normal.string() + ".parts";
}

std::uint64_t planarShardBytes(const PyramidLayout& layout) {
    const auto side = std::uint64_t(layout.shardPatches()) * std::uint64_t(layout.patchQuads()) + 3;
    const std::uint64_t window = side * side * 5;  // a coarse shard's samples
    const std::uint64_t even = window / 4;         // its even samples, and a child's
    return detail::planarBandBytes(layout, layout.shardPatches()) + window + 2 * even;
}

std::vector<ShardId> shardInputs(const PyramidLayout& layout, const ShardId& shard) {
    std::vector<ShardId> inputs;
    if (shard.level >= layout.finestLevel()) return inputs;
    const int finer = shard.level + 1;
    for (std::int64_t y = std::max<std::int64_t>(0, 2 * shard.y - 1);
         y <= std::min(2 * shard.y + 2, layout.shardsY(finer) - 1); ++y)
        for (std::int64_t x = std::max<std::int64_t>(0, 2 * shard.x - 1);
             x <= std::min(2 * shard.x + 2, layout.shardsX(finer) - 1); ++x)
            inputs.push_back(ShardId{finer, x, y});
    return inputs;
}

Result<ShardPlan> planPyramidShards(DemReader& reader, const fs::path& output,
                                    const PyramidBuildOptions& options) {
    return openPlan(reader, output, options, true);
}

Result<ShardBuildSummary> buildPyramidShard(DemReader& reader, const fs::path& output,
                                            const ShardId& shard,
                                            const PyramidBuildOptions& options) {
    const auto start = BuildClock::now();
    auto planned = openPlan(reader, output, options, true);
    if (!planned) return planned.error();
    const ShardPlan& plan = planned.value();
    const PyramidLayout& layout = plan.layout;
    if (shard.level < 0 || shard.level > layout.finestLevel() || !layout.contains(shard))
        return Error{
            fmt::format("{}: no shard {}/{}/{} in this pyramid ({} levels; level {} has "
                        "{} × {} shards)",
                        output.string(), shard.level, shard.x, shard.y, layout.levelCount(),
                        std::clamp(shard.level, 0, layout.finestLevel()),
                        layout.shardsX(std::clamp(shard.level, 0, layout.finestLevel())),
                        layout.shardsY(std::clamp(shard.level, 0, layout.finestLevel())))};
    const DemInfo& dem = reader.info();
    const std::int64_t w = dem.width, h = dem.height;
    const PatchRect rect = patchesOf(layout, shard);
    const int q = layout.patchQuads();
    const bool finest = shard.level == layout.finestLevel();
    const bool lastX = shard.x == layout.shardsX(shard.level) - 1;
    const bool lastY = shard.y == layout.shardsY(shard.level) - 1;

    PyramidBuildOptions taskOptions = options;
    taskOptions.progress = nullptr;  // a task's own fraction; buildPyramidByShards says the whole's
    detail::LevelBuilder builder(reader, layout, taskOptions, plan.staging,
                                 detail::planarMaskStored(dem));
    std::optional<EvenBlock> even;
    if (shard.level > 0) even.emplace(evenRangeOf(layout, shard, w, h));
    detail::EvenRows* coarser = even ? &*even : nullptr;
    const detail::OwnedSamples owned{rect.x0 * q, rect.y0 * q, lastX ? w : rect.x1 * q,
                                     lastY ? h : rect.y1 * q};
    if (finest) {
        if (Status built = builder.runFinestRegion(rect, owned, coarser); !built)
            return built.error();
        // The DEM's last column and row, for the coarser levels' samples beyond the DEM.
        const detail::DemEdges& edges = builder.edges();
        if (lastX)
            if (Status written = detail::writeEdge(detail::edgePath(plan.staging, true, shard.y),
                                                   {edges.firstRow, edges.lastColumnHeights});
                !written)
                return written.error();
        if (lastY) {
            detail::EdgeRun south{owned.x0, {}};
            for (std::int64_t x = owned.x0; x < owned.x1; ++x)
                south.values.push_back(
                    edges.lastRowHeights.at(static_cast<std::size_t>(x - edges.firstColumn)));
            if (Status written =
                    detail::writeEdge(detail::edgePath(plan.staging, false, shard.x), south);
                !written)
                return written.error();
        }
    } else {
        ChildBounds children;
        auto inside =
            CarriedSamples::load(plan.staging, layout, shard, w, h, plan.fingerprint, children);
        if (!inside) return inside.error();
        CarriedEdges edges(plan.staging, layout);
        detail::CoarseRows rows(*inside.value(), edges, layout.levelStep(shard.level), w);
        if (Status built =
                builder.runCoarseRegion(shard.level, rect, rows, std::move(children), coarser);
            !built)
            return built.error();
    }

    detail::ShardCarry carry;
    carry.fingerprint = plan.fingerprint;
    carry.shard = shard;
    carry.patches = builder.patches();
    carry.levelMaxError = builder.levelMaxError()[static_cast<std::size_t>(shard.level)];
    if (finest && builder.quantization())
        carry.finestLargestQuantErrorM = builder.quantization()->finestLargestErrorM;
    carry.statistics = builder.statistics();
    carry.phases = builder.phases();
    carry.bounds = builder.bounds();
    if (even) even->moveTo(carry);
    carry.seconds = secondsSince(start);
    if (Status written = detail::writeCarry(detail::carryPath(plan.staging, shard), carry);
        !written)
        return written.error();

    ShardBuildSummary summary;
    summary.shard = shard;
    summary.patches = carry.patches;
    std::error_code ec;
    summary.bytes = fs::file_size(plan.staging / layout.shardPath(shard), ec);
    summary.seconds = carry.seconds;
    return summary;
}

Result<PyramidBuildSummary> mergePyramidShards(DemReader& reader, const fs::path& output,
                                               const PyramidBuildOptions& options) {
    auto planned = openPlan(reader, output, options, false);
    if (!planned) return planned.error();
    const ShardPlan& plan = planned.value();
    const PyramidLayout& layout = plan.layout;

    detail::PlanarBuildTotals totals;
    totals.levelMaxError.assign(static_cast<std::size_t>(layout.levelCount()), 0.0f);
    if (options.maxErrorM > 0.0) totals.quantization = ManifestQuantization{options.maxErrorM};
    for (int level = layout.finestLevel(); level >= 0; --level) {
        for (std::int64_t y = 0; y < layout.shardsY(level); ++y)
            for (std::int64_t x = 0; x < layout.shardsX(level); ++x) {
                const ShardId shard{level, x, y};
                std::error_code ec;
                const fs::path shardFile = plan.staging / layout.shardPath(shard);
                if (!fs::is_regular_file(shardFile, ec))
                    return Error{shardFile.string() + ": missing (shard " +
                                 fmt::format("{}/{}/{}", level, x, y) + " was not built)"};
                auto read = readChildCarry(plan.staging, shard, plan.fingerprint, false);
                if (!read) return read.error();
                const detail::ShardCarry& c = read.value();
                float& levelMax = totals.levelMaxError[static_cast<std::size_t>(level)];
                levelMax = std::max(levelMax, c.levelMaxError);
                totals.patches += c.patches;
                totals.phases.readSeconds += c.phases.readSeconds;
                totals.phases.boundsSeconds += c.phases.boundsSeconds;
                totals.phases.writeSeconds += c.phases.writeSeconds;
                totals.seconds += c.seconds;
                if (level != layout.finestLevel()) continue;
                totals.statistics.add(c.statistics);
                if (totals.quantization)
                    totals.quantization->finestLargestErrorM = std::max(
                        totals.quantization->finestLargestErrorM, c.finestLargestQuantErrorM);
            }
    }

    auto adopted = PartialBuildFolder::adopt(output, plan.staging, options.overwrite);
    if (!adopted) return adopted.error();
    auto summary = detail::finishPlanarBuild(reader, layout, totals, plan.staging);
    if (!summary) return summary.error();
    detail::removeStagingFiles(plan.staging);
    summary.value().bytes = folderBytes(plan.staging);
    if (Status committed = adopted.value().commit(); !committed) return committed.error();
    return summary;
}

Result<PyramidBuildSummary> buildPyramidByShards(DemReader& reader, const fs::path& output,
                                                 const PyramidBuildOptions& options) {
    std::error_code ec;
    if (fs::exists(output, ec) && !options.overwrite)
        return Error{output.string() + ": already exists (pass --overwrite to replace it)"};
    auto planned = planPyramidShards(reader, output, options);
    if (!planned) return planned.error();
    const ShardPlan& plan = planned.value();
    const PyramidLayout& layout = plan.layout;
    detail::StagingCleanup cleanup(plan.staging);

    double total = 0.0, done = 0.0;
    for (int level = 0; level < layout.levelCount(); ++level)
        total += double(layout.patchCount(level));
    for (int level = layout.finestLevel(); level >= 0; --level)
        for (std::int64_t y = 0; y < layout.shardsY(level); ++y)
            for (std::int64_t x = 0; x < layout.shardsX(level); ++x) {
                auto built = buildPyramidShard(reader, output, ShardId{level, x, y}, options);
                if (!built) return built.error();
                done += double(built.value().patches);
                if (options.progress) options.progress({level, std::min(1.0, done / total)});
            }
    auto merged = mergePyramidShards(reader, output, options);
    if (merged) cleanup.merged();
    return merged;
}

}  // namespace terrain::io
