// Region builds (PyramidShards.h) against their promises: shards built one at a time, in
// any order the dependencies allow, then merged, are the whole build's files byte for byte
// (procedural, lossy, odd shard sizes, no-data runs across shards, real DEMs); a task run
// twice writes the same bytes; the merge refuses a missing or foreign shard and writes
// nothing; a raster too wide for the memory budget is built shard by shard.
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/build/PyramidShards.h"

#include "PyramidFiles.h"
#include "SharedData.h"
#include "TempFolder.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;
using test::fileBytes;
using test::pyramidFiles;
using test::TempFolder;
constexpr PyramidSurface kPlane = PyramidSurface::Plane;

void expectSameFiles(const fs::path& whole, const fs::path& merged) {
    const auto a = pyramidFiles(whole), b = pyramidFiles(merged);
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [path, bytes] : a) {
        auto found = b.find(path);
        ASSERT_NE(found, b.end()) << path << " is missing from the region build";
        EXPECT_TRUE(found->second == bytes) << path << " differs";
    }
}

std::unique_ptr<DemReader> open(const std::string& input, const DemOpenOptions& options = {}) {
    auto reader = openDem({input}, options);
    EXPECT_TRUE(reader.ok()) << (reader.ok() ? "" : reader.error().message);
    return reader.ok() ? std::move(reader).value() : nullptr;
}

// Every shard as its own task, finest level first, each level's shards in reverse order
// (not the whole build's), then the merge.
void buildByTasks(DemReader& reader, const fs::path& out, const PyramidBuildOptions& options) {
    auto plan = planPyramidShards(kPlane, reader, out, options);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    const PyramidLayout& layout = plan.value().layout;
    for (int level = layout.finestLevel(); level >= 0; --level)
        for (std::int64_t y = layout.shardsY(level) - 1; y >= 0; --y)
            for (std::int64_t x = layout.shardsX(level) - 1; x >= 0; --x) {
                auto built = buildPyramidShard(kPlane, reader, out, ShardId{level, x, y}, options);
                ASSERT_TRUE(built.ok()) << built.error().message;
            }
    auto merged = mergePyramidShards(kPlane, reader, out, options);
    ASSERT_TRUE(merged.ok()) << merged.error().message;
    EXPECT_FALSE(fs::exists(shardStagingFolder(out)));
    EXPECT_FALSE(fs::exists(out / "tmp"));
}

void expectRegionBuildEqualsWholeBuild(DemReader& reader, PyramidBuildOptions options) {
    TempFolder tmp;
    options.threads = 2;
    auto whole = buildPyramid(reader, tmp.path() / "whole", options);
    ASSERT_TRUE(whole.ok()) << whole.error().message;
    buildByTasks(reader, tmp.path() / "tasks", options);
    expectSameFiles(tmp.path() / "whole", tmp.path() / "tasks");
    auto byShards = buildPyramidByShards(kPlane, reader, tmp.path() / "by-shards", options);
    ASSERT_TRUE(byShards.ok()) << byShards.error().message;
    expectSameFiles(tmp.path() / "whole", tmp.path() / "by-shards");
    EXPECT_EQ(byShards.value().manifest.statistics.validSamples,
              whole.value().manifest.statistics.validSamples);
    EXPECT_TRUE(PyramidReader::open(tmp.path() / "tasks").ok());
}

PyramidBuildOptions withShards(int shardPatches, int patchSamples = 129) {
    PyramidBuildOptions options;
    options.shardPatches = shardPatches;
    options.patchSamples = patchSamples;
    return options;
}

TEST(PyramidShards, ProceduralRegionBuildEqualsTheWholeBuild) {
    auto reader = open("procedural:width=1100,height=700,seed=3");
    expectRegionBuildEqualsWholeBuild(*reader, withShards(2));
}

TEST(PyramidShards, OddShardSizesAndOneShardPerPatch) {
    auto reader = open("procedural:width=700,height=530,seed=1");
    expectRegionBuildEqualsWholeBuild(*reader, withShards(1, 65));
    expectRegionBuildEqualsWholeBuild(*reader, withShards(3, 33));
}

TEST(PyramidShards, LossyAndIndependentPatches) {
    auto reader = open("procedural:size=1000,seed=5");
    PyramidBuildOptions lossy = withShards(3);
    lossy.maxErrorM = 0.5;
    expectRegionBuildEqualsWholeBuild(*reader, lossy);
    PyramidBuildOptions independent = withShards(2);
    independent.parentPrediction = false;
    expectRegionBuildEqualsWholeBuild(*reader, independent);
}

// An int16 DEM with no-data runs that cross shards, start rows, end rows, and fill whole
// rows: the fill (linear along the whole row) must find the valid samples beyond a shard.
class HoleyDem final : public DemReader {
public:
    HoleyDem(std::int64_t width, std::int64_t height) {
        m_info.path = "holey";
        m_info.readerName = "test";
        m_info.inputs = {"holey"};
        m_info.width = width;
        m_info.height = height;
        m_info.sampleType = "int16";
        m_info.noDataValue = -32768.0;
    }
    const DemInfo& info() const override { return m_info; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        for (std::int64_t r = 0; r < rows; ++r)
            for (std::int64_t c = 0; c < width; ++c)
                out[static_cast<std::size_t>(r * width + c)] = sample(x0 + c, y0 + r);
        return {};
    }

private:
    float sample(std::int64_t x, std::int64_t y) const {
        const bool hole = y % 97 == 5                                  // a whole row
                          || (y % 7 == 0 && x > 100 && x < 600)        // runs across shards
                          || (y % 11 == 3 && x < 300)                  // from the west edge
                          || (y % 13 == 4 && x > m_info.width - 400);  // to the east edge
        if (hole) return std::numeric_limits<float>::quiet_NaN();
        return static_cast<float>((x * 7 + y * 3) % 200 + ((x / 50 + y / 40) % 3) * 40);
    }
    DemInfo m_info;
};

TEST(PyramidShards, NoDataRunsAcrossShardsFillAsInTheWholeBuild) {
    HoleyDem dem(900, 600);
    expectRegionBuildEqualsWholeBuild(dem, withShards(1, 65));
}

TEST(PyramidShards, RealDemsRegionBuildEqualsTheWholeBuild) {
    TERRAIN_SHARED_DATA_OR_SKIP(luxembourg, "luxembourg_elev_30s.tif");
    TERRAIN_SHARED_DATA_OR_SKIP(rainier, "srtm3_n46w122_rainier.tif");
    auto border = open(luxembourg.string());  // no-data outside the border
    expectRegionBuildEqualsWholeBuild(*border, withShards(1, 33));
    auto voids = open(rainier.string());  // SRTM voids
    expectRegionBuildEqualsWholeBuild(*voids, withShards(2));
}

TEST(PyramidShards, ATaskRunTwiceWritesTheSameBytes) {
    TempFolder tmp;
    auto reader = open("procedural:size=600,seed=2");
    const fs::path out = tmp.path() / "twice";
    const PyramidBuildOptions options = withShards(2);
    auto plan = planPyramidShards(kPlane, *reader, out, options);
    ASSERT_TRUE(plan.ok());
    const PyramidLayout& layout = plan.value().layout;
    const ShardId shard{layout.finestLevel(), 1, 0};
    const fs::path file = plan.value().staging / layout.shardPath(shard);
    ASSERT_TRUE(buildPyramidShard(kPlane, *reader, out, shard, options).ok());
    const std::string first = fileBytes(file);
    ASSERT_TRUE(buildPyramidShard(kPlane, *reader, out, shard, options).ok());
    EXPECT_TRUE(fileBytes(file) == first);
    // Nothing but the shard, its carry, the DEM edge files and the plan: no temporary left.
    for (const auto& entry : fs::recursive_directory_iterator(plan.value().staging))
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST(PyramidShards, ACoarseShardNeedsTheShardsBeneathIt) {
    TempFolder tmp;
    auto reader = open("procedural:size=600,seed=2");
    const fs::path out = tmp.path() / "early";
    const PyramidBuildOptions options = withShards(2);
    auto plan = planPyramidShards(kPlane, *reader, out, options);
    ASSERT_TRUE(plan.ok());
    const int coarse = plan.value().layout.finestLevel() - 1;
    auto built = buildPyramidShard(kPlane, *reader, out, ShardId{coarse, 0, 0}, options);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.error().message.find(".carry: missing"), std::string::npos)
        << built.error().message;
    auto outside = buildPyramidShard(kPlane, *reader, out, ShardId{coarse, 99, 0}, options);
    ASSERT_FALSE(outside.ok());
    EXPECT_NE(outside.error().message.find("no shard"), std::string::npos);
}

TEST(PyramidShards, MergeRefusesAMissingShardAndWritesNothing) {
    TempFolder tmp;
    auto reader = open("procedural:size=600,seed=2");
    const fs::path out = tmp.path() / "incomplete";
    const PyramidBuildOptions options = withShards(2);
    auto plan = planPyramidShards(kPlane, *reader, out, options);
    ASSERT_TRUE(plan.ok());
    const PyramidLayout& layout = plan.value().layout;
    const int finest = layout.finestLevel();
    for (std::int64_t y = 0; y < layout.shardsY(finest); ++y)
        for (std::int64_t x = 0; x < layout.shardsX(finest); ++x)
            if (!(x == 1 && y == 1)) {
                ASSERT_TRUE(
                    buildPyramidShard(kPlane, *reader, out, ShardId{finest, x, y}, options).ok());
            }
    auto merged = mergePyramidShards(kPlane, *reader, out, options);
    ASSERT_FALSE(merged.ok());
    EXPECT_NE(merged.error().message.find(layout.shardPath(ShardId{finest, 1, 1}).string()),
              std::string::npos)
        << merged.error().message;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(plan.value().staging / "manifest.json"));
    EXPECT_TRUE(fs::exists(plan.value().staging / "plan.json")) << "the built shards are kept";

    // Finished, the same staging folder merges.
    ASSERT_TRUE(buildPyramidShard(kPlane, *reader, out, ShardId{finest, 1, 1}, options).ok());
    for (int level = finest - 1; level >= 0; --level)
        for (std::int64_t y = 0; y < layout.shardsY(level); ++y)
            for (std::int64_t x = 0; x < layout.shardsX(level); ++x)
                ASSERT_TRUE(
                    buildPyramidShard(kPlane, *reader, out, ShardId{level, x, y}, options).ok());
    EXPECT_TRUE(mergePyramidShards(kPlane, *reader, out, options).ok());
    EXPECT_TRUE(PyramidReader::open(out).ok());
}

TEST(PyramidShards, ShardsOfAnotherBuildAreRefused) {
    TempFolder tmp;
    auto reader = open("procedural:size=600,seed=2");
    const fs::path out = tmp.path() / "mixed";
    ASSERT_TRUE(planPyramidShards(kPlane, *reader, out, withShards(2)).ok());
    PyramidBuildOptions other = withShards(2);
    other.compressionLevel = 9;
    auto built = buildPyramidShard(kPlane, *reader, out, ShardId{0, 0, 0}, other);
    ASSERT_FALSE(built.ok());
    EXPECT_NE(built.error().message.find("other options"), std::string::npos)
        << built.error().message;
    auto otherSource = open("procedural:size=600,seed=3");
    auto merged = mergePyramidShards(kPlane, *otherSource, out, withShards(2));
    ASSERT_FALSE(merged.ok());
    EXPECT_NE(merged.error().message.find(shardStagingFolder(out).string()), std::string::npos);
}

TEST(PyramidShards, TooWideForTheBudgetIsBuiltShardByShard) {
    TempFolder tmp;
    auto reader = open("procedural:width=4097,height=400,seed=4");
    PyramidBuildOptions options = withShards(4);
    options.threads = 2;
    auto whole = buildPyramid(*reader, tmp.path() / "whole", options);
    ASSERT_TRUE(whole.ok());
    options.memoryBudgetBytes = std::uint64_t{75} << 20;  // a band across needs ~80 MiB
    auto narrow = buildPyramid(*reader, tmp.path() / "narrow", options);
    ASSERT_TRUE(narrow.ok()) << narrow.error().message;
    ASSERT_FALSE(narrow.value().warnings.empty());
    EXPECT_NE(narrow.value().warnings.front().find("shard by shard"), std::string::npos);
    expectSameFiles(tmp.path() / "whole", tmp.path() / "narrow");
}

TEST(PyramidShards, ABudgetTooSmallForOneShardIsAClearError) {
    TempFolder tmp;
    auto reader = open("procedural:width=2000000,height=300");
    PyramidBuildOptions options;
    options.memoryBudgetBytes = 64u << 20;
    auto result = buildPyramid(*reader, tmp.path() / "wide", options);
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("--shard-patches"), std::string::npos)
        << result.error().message;
    // The one message of a build over its budget (BuildBudget.h).
    EXPECT_NE(result.error().message.find("more than --memory (64 MiB); "), std::string::npos)
        << result.error().message;
    EXPECT_TRUE(fs::is_empty(tmp.path()));
}

}  // namespace
}  // namespace terrain::io
