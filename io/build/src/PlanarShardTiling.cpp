// The plane's shard tiling (ShardTiling.h, PyramidShards.h): every shard of every level, a
// finest shard built from the source window it covers, a coarser one from the even samples
// and bounds of the finer shards beneath and beside it (their carries), never from the
// source: the whole build's files, byte for byte.
#include "ShardTiling.h"

#include "BuildBudget.h"
#include "BuildClock.h"
#include "CarryArchive.h"
#include "LevelBuilder.h"
#include "PlanarManifest.h"
#include "RegionStaging.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstring>
#include <fstream>
#include <map>

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

// Bytes a shard task needs at most, about: one shard's band, records and samples.
std::uint64_t planarShardBytes(const PyramidLayout& layout) {
    const auto side = std::uint64_t(layout.shardPatches()) * std::uint64_t(layout.patchQuads()) + 3;
    const std::uint64_t window = side * side * 5;  // a coarse shard's samples
    const std::uint64_t even = window / 4;         // its even samples, and a child's
    return detail::planarBandBytes(layout, layout.shardPatches()) + window + 2 * even;
}

// One edge of the DEM kept by a finest shard on the east or south edge for every coarser
// level: values at DEM rows (east) or columns (south) first, first + 1, …
struct EdgeRun {
    std::int64_t first = 0;
    std::vector<float> values;
};

constexpr char kEdgeMagic[8] = {'T', 'R', 'E', 'D', 'G', 'E', '0', '1'};

// "tmp/edges/east-<sy>.f32" and "tmp/edges/south-<sx>.f32" in the staging folder.
fs::path edgePath(const fs::path& staging, bool east, std::int64_t index) {
    return staging / "tmp" / "edges" / fmt::format("{}-{}.f32", east ? "east" : "south", index);
}

Status writeEdge(const fs::path& path, const EdgeRun& run) {
    detail::CarryWriter w;
    w.field(kEdgeMagic);
    w.field(run.first);
    w.values(run.values);
    return detail::writeFileAtomically(path, w.bytes());
}

Result<EdgeRun> readEdge(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path.string() + ": missing (the edge shard's task has not finished)"};
    detail::CarryReader r(in);
    char magic[8] = {};
    r.field(magic);
    EdgeRun run;
    r.field(run.first);
    r.values(run.values);
    if (r.failed() || std::memcmp(magic, kEdgeMagic, sizeof magic) != 0)
        return Error{path.string() + ": not a DEM edge file, or truncated"};
    return run;
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
    void moveTo(detail::RegionCarry& carry) {
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

// A coarse region's samples on the DEM, gathered from the carries of the finer shards
// beneath it, and its children's bounds.
class CarriedSamples final : public detail::InsideSamples {
public:
    static Result<std::unique_ptr<CarriedSamples>> load(const ShardPlan& plan, const ShardId& shard,
                                                        std::int64_t w, std::int64_t h,
                                                        ChildBounds& children,
                                                        std::vector<ShardId>& builtFrom) {
        const fs::path& staging = plan.staging;
        const PyramidLayout& layout = plan.layout;
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
        for (const ShardId& child : shardInputs(plan, shard)) {
            auto read = detail::readShardCarry(staging, child, plan.fingerprint, true);
            if (!read) return read.error();
            builtFrom.push_back(child);
            const detail::RegionCarry& c = read.value();
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
            auto read = readEdge(edgePath(m_staging, east, index));
            if (!read) return read.error();
            found = m_runs.emplace(std::pair{east, index}, std::move(read).value()).first;
        }
        const EdgeRun& run = found->second;
        if (sample < run.first || sample - run.first >= std::ssize(run.values))
            return Error{edgePath(m_staging, east, index).string() + ": does not hold DEM sample " +
                         std::to_string(sample)};
        return run.values[static_cast<std::size_t>(sample - run.first)];
    }

    fs::path m_staging;
    const PyramidLayout& m_layout;
    std::map<std::pair<bool, std::int64_t>, EdgeRun> m_runs;
};

class PlanarShardTiling final : public detail::ShardTiling {
public:
    PlanarShardTiling(DemReader& reader, const PyramidBuildOptions& options)
        : m_reader(reader), m_voids(reader), m_options(options) {}

    static Result<std::unique_ptr<detail::ShardTiling>> open(DemReader& reader,
                                                             const fs::path& output,
                                                             const PyramidBuildOptions& options) {
        const DemInfo& dem = reader.info();
        auto layout = PyramidLayout::create(dem.width, dem.height, options.patchSamples,
                                            options.blockQuads, options.shardPatches);
        if (!layout) return Error{dem.path + ": " + layout.error().message};
        auto tiling = std::make_unique<PlanarShardTiling>(reader, options);
        ShardPlan& plan = tiling->m_plan;
        plan.surface = PyramidSurface::Plane;
        plan.layout = layout.value();
        plan.staging = shardStagingFolder(output);
        plan.fingerprint = planarFingerprint(dem, plan.layout, options);
        plan.taskBytes = planarShardBytes(plan.layout);
        plan.shards.resize(static_cast<std::size_t>(plan.layout.levelCount()));
        for (int level = 0; level < plan.layout.levelCount(); ++level)
            for (std::int64_t y = 0; y < plan.layout.shardsY(level); ++y)
                for (std::int64_t x = 0; x < plan.layout.shardsX(level); ++x)
                    plan.shards[static_cast<std::size_t>(level)].push_back({level, x, y});
        return std::unique_ptr<detail::ShardTiling>(std::move(tiling));
    }

    std::string taskName() const override {
        return fmt::format("a shard of {} × {} patches", m_plan.layout.shardPatches(),
                           m_plan.layout.shardPatches());
    }

    Status checkShard(const ShardId& shard, const fs::path& output) const override {
        const PyramidLayout& layout = m_plan.layout;
        if (shard.level >= 0 && shard.level <= layout.finestLevel() && layout.contains(shard))
            return {};
        const int level = std::clamp(shard.level, 0, layout.finestLevel());
        return Error{fmt::format(
            "{}: no shard {}/{}/{} in this pyramid ({} levels; level {} has {} × {} shards)",
            output.string(), shard.level, shard.x, shard.y, layout.levelCount(), level,
            layout.shardsX(level), layout.shardsY(level))};
    }

    Result<detail::RegionCarry> buildShard(const ShardId& shard) override {
        const PyramidLayout& layout = m_plan.layout;
        const DemInfo& dem = m_reader.info();
        const std::int64_t w = dem.width, h = dem.height;
        const PatchRect rect = patchesOf(layout, shard);
        const int q = layout.patchQuads();
        const bool finest = shard.level == layout.finestLevel();
        const bool lastX = shard.x == layout.shardsX(shard.level) - 1;
        const bool lastY = shard.y == layout.shardsY(shard.level) - 1;

        PyramidBuildOptions taskOptions = m_options;
        taskOptions.progress = nullptr;  // a task's own fraction; the engine says the whole's
        detail::LevelBuilder builder(m_reader, m_voids, layout, taskOptions, m_plan.staging,
                                     detail::planarMaskStored(dem));
        std::optional<EvenBlock> even;
        if (shard.level > 0) even.emplace(evenRangeOf(layout, shard, w, h));
        detail::EvenRows* coarser = even ? &*even : nullptr;
        const detail::OwnedSamples owned{rect.x0 * q, rect.y0 * q, lastX ? w : rect.x1 * q,
                                         lastY ? h : rect.y1 * q};
        detail::RegionCarry carry;
        if (finest) {
            if (Status built = builder.runFinestRegion(rect, owned, coarser); !built)
                return built.error();
            // The DEM's last column and row, for the coarser levels' samples beyond the DEM.
            const detail::DemEdges& edges = builder.edges();
            if (lastX)
                if (Status written = writeEdge(edgePath(m_plan.staging, true, shard.y),
                                               {edges.firstRow, edges.lastColumnHeights});
                    !written)
                    return written.error();
            if (lastY) {
                EdgeRun south{owned.x0, {}};
                for (std::int64_t x = owned.x0; x < owned.x1; ++x)
                    south.values.push_back(
                        edges.lastRowHeights.at(static_cast<std::size_t>(x - edges.firstColumn)));
                if (Status written = writeEdge(edgePath(m_plan.staging, false, shard.x), south);
                    !written)
                    return written.error();
            }
        } else {
            ChildBounds children;
            auto inside = CarriedSamples::load(m_plan, shard, w, h, children, carry.builtFrom);
            if (!inside) return inside.error();
            CarriedEdges edges(m_plan.staging, layout);
            detail::CoarseRows rows(*inside.value(), edges, layout.levelStep(shard.level), w);
            if (Status built =
                    builder.runCoarseRegion(shard.level, rect, rows, std::move(children), coarser);
                !built)
                return built.error();
        }
        carry.patches = builder.patches();
        carry.levelMaxError = builder.levelMaxError()[static_cast<std::size_t>(shard.level)];
        if (finest && builder.quantization())
            carry.finestLargestQuantErrorM = builder.quantization()->finestLargestErrorM;
        carry.statistics = builder.statistics();
        carry.phases = builder.phases();
        carry.bounds = builder.bounds();
        if (even) even->moveTo(carry);
        return carry;
    }

    Result<PyramidManifest> manifest(const detail::RegionTotals& totals,
                                     std::vector<std::string>& warnings) override {
        return detail::planarManifest(m_reader, m_plan.layout, totals.statistics,
                                      totals.levelMaxError, totals.quantization, {}, warnings);
    }

private:
    DemReader& m_reader;
    detail::SourceVoids m_voids;  // found once for every shard this process builds
    const PyramidBuildOptions& m_options;
};

}  // namespace

Result<std::unique_ptr<detail::ShardTiling>> detail::planarShardTiling(
    DemReader& reader, const fs::path& output, const PyramidBuildOptions& options) {
    return PlanarShardTiling::open(reader, output, options);
}

}  // namespace terrain::io
