// Globe region builds (PyramidShards.h) against their promises, at the places a globe is hard (a
// cap over a pole, a strip across the antimeridian, a whole Earth with its repeated seam
// column, voids whose fill runs across blocks and shards): the patches present, their heights
// (apron included) and their children are the whole build's to the bit; the finest Err(P) is
// the whole build's and every coarser one at least it; every valid source sample is within
// Err(P) of every level, read back from the files; shards built one task at a time in another
// order are the same bytes; the merge refuses a missing shard or one built before a shard
// beneath it, and writes nothing; a source over the memory budget is built by shards.
#include "terrain/dem/OpenDem.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/PyramidShards.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/build/PyramidSourceCheck.h"

#include "GeographicFunctionDem.h"
#include "GlobeTestSources.h"
#include "PyramidFiles.h"
#include "SharedData.h"
#include "TempFolder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;
using globe::GlobePatchId;
using test::GeographicFunctionDem;
using test::hills;
using test::pyramidFiles;
using test::TempFolder;
constexpr PyramidSurface kGlobe = PyramidSurface::Globe;

// One thread: these builds are many small shards, and the suite runs under sanitizers too;
// RegionalSourceAtHighLatitude builds with two.
PyramidBuildOptions smallPatches() {
    PyramidBuildOptions options = test::smallGlobePatches();
    options.threads = 1;
    return options;
}

// The region build against the whole build of the same source: the same patches with the same
// tiles and children; Err(P) equal at the finest level, never smaller above; the manifests'
// statistics equal; and the region build's bounds hold at every valid source sample.
void expectRegionBuildMatchesWholeBuild(DemReader& source, PyramidBuildOptions options,
                                        int measuredLevels = 0) {
    TempFolder temp;
    const fs::path whole = temp.path() / "whole.pyramid";
    const fs::path region = temp.path() / "region.pyramid";
    auto w = buildGlobePyramid(source, whole, options);
    ASSERT_TRUE(w) << w.error().message;
    // Every level above the finest nested, or those above `measuredLevels` (the default
    // measures these small sources at their samples at every level, and so builds the whole
    // build's bounds, which MeasuredLevelsAreTheWholeBuildsBytes checks).
    options.globeMeasuredLevels = measuredLevels;
    auto r = buildPyramidByShards(kGlobe, source, region, options);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_FALSE(fs::exists(shardStagingFolder(region)));

    const PyramidManifest& wm = w.value().manifest;
    const PyramidManifest& rm = r.value().manifest;
    ASSERT_TRUE(rm.globe);
    EXPECT_EQ(rm.globe->faceFinestLevel, wm.globe->faceFinestLevel);
    EXPECT_EQ(rm.statistics.validSamples, wm.statistics.validSamples);
    EXPECT_EQ(rm.noData.samples, wm.noData.samples);
    EXPECT_EQ(rm.statistics.minHeight, wm.statistics.minHeight);
    EXPECT_EQ(rm.statistics.maxHeight, wm.statistics.maxHeight);
    EXPECT_GE(rm.statistics.rootError, wm.statistics.rootError);
    ASSERT_EQ(rm.levels.size(), wm.levels.size());
    for (std::size_t l = 0; l < wm.levels.size(); ++l) {
        EXPECT_EQ(rm.levels[l].presentPatches, wm.levels[l].presentPatches) << "level " << l;
        EXPECT_EQ(rm.levels[l].presentShards, wm.levels[l].presentShards) << "level " << l;
    }

    auto wr = PyramidReader::open(whole);
    auto rr = PyramidReader::open(region);
    ASSERT_TRUE(wr && rr);
    const int finest = wm.globe->faceFinestLevel;
    const PyramidLayout& layout = wr.value().layout();
    std::int64_t compared = 0;
    // Every patch of every shard either build holds (their shard lists are equal, above).
    for (const ManifestLevel& level : wm.levels)
        for (const ShardId& shard : level.presentShards)
            for (std::int64_t y = layout.shardFirstY(shard);
                 y < layout.shardFirstY(shard) + layout.shardCountY(shard); ++y)
                for (std::int64_t x = layout.shardFirstX(shard);
                     x < layout.shardFirstX(shard) + layout.shardCountX(shard); ++x) {
                    const PatchId id{level.level, x, y};
                    auto a = wr.value().patchInfo(id);
                    auto b = rr.value().patchInfo(id);
                    ASSERT_TRUE(a && b);
                    ASSERT_EQ(a.value().present, b.value().present)
                        << "level " << level.level << " (" << x << ", " << y << ")";
                    if (!a.value().present) continue;
                    EXPECT_EQ(a.value().presentChildren, b.value().presentChildren);
                    if (level.level == layout.finestLevel())
                        EXPECT_EQ(a.value().error, b.value().error);
                    else
                        EXPECT_GE(b.value().error, a.value().error);
                    auto ha = wr.value().readPatch(id);
                    auto hb = rr.value().readPatch(id);
                    ASSERT_TRUE(ha && hb);
                    ASSERT_EQ(ha.value().heights, hb.value().heights)
                        << "level " << level.level << " (" << x << ", " << y << ")";
                    EXPECT_EQ(ha.value().valid, hb.value().valid);
                    ++compared;
                }
    EXPECT_EQ(compared, r.value().patches);
    ::testing::Test::RecordProperty("patchesCompared", static_cast<int>(compared));

    auto report = checkErrorBoundsAgainstSource(region, source);
    ASSERT_TRUE(report) << report.error().message;
    EXPECT_EQ(report.value().violationCount, 0);
    EXPECT_EQ(report.value().samplesChecked, rm.statistics.validSamples * (finest + 1));
}

TEST(GlobeShards, RegionalSourceAtHighLatitude) {
    GeographicFunctionDem source(8.0, 61.0, 200, 120, 0.01, 0.005, hills);
    PyramidBuildOptions options = smallPatches();
    options.threads = 2;  // the samples' rows and the patches in parallel
    expectRegionBuildMatchesWholeBuild(source, options);
}

TEST(GlobeShards, CapOverTheNorthPole) {
    GeographicFunctionDem source(-180.0, 90.0, 360, 20, 1.0, 0.1,
                                 [](double lat, double lon) { return hills(lat, lon) + 200.0f; });
    expectRegionBuildMatchesWholeBuild(source, smallPatches());
}

// The fan to the pole (GlobePyramid.TheSurfaceMeetsThePoleInOnePoint) stands on the mean of
// the filled edge row, which a region build reads for itself: voids in that row, filled by
// the membrane, give the whole build's pole to the bit.
TEST(GlobeShards, ThePoleOfAGridWithVoidsInItsEdgeRow) {
    GeographicFunctionDem source(-180.0, 90.0, 360, 20, 1.0, 0.1, [](double lat, double lon) {
        if (lat > 89.9 && std::fmod(lon + 180.0, 90.0) < 20.0)
            return std::numeric_limits<float>::quiet_NaN();
        return hills(lat, lon) + 200.0f + 40.0f * float(std::sin(lon * 0.05));
    });
    expectRegionBuildMatchesWholeBuild(source, smallPatches());
}

// Native leaves in a region build (docs/globe.md, "Native leaves"): the merge builds the
// source's native grid by shards, read window by window from the source (filled as the
// shards fill it, its margin tapered from the edge samples), and it is the whole build's:
// the same patches, the same heights to the bit; the globe pyramid's manifest names it.
void expectNativeGridMatchesWholeBuild(DemReader& source) {
    TempFolder temp;
    PyramidBuildOptions options = smallPatches();
    options.globeNativeLeaves = true;
    const fs::path whole = temp.path() / "whole.pyramid";
    const fs::path region = temp.path() / "region.pyramid";
    auto w = buildGlobePyramid(source, whole, options);
    ASSERT_TRUE(w) << w.error().message;
    auto r = buildPyramidByShards(kGlobe, source, region, options);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_FALSE(fs::exists(shardStagingFolder(region)));
    ASSERT_TRUE(r.value().manifest.globe);
    ASSERT_EQ(r.value().manifest.globe->sources.size(), 1u);
    const std::string native = r.value().manifest.globe->sources[0].native;
    ASSERT_EQ(native, w.value().manifest.globe->sources[0].native);
    ASSERT_FALSE(native.empty());
    EXPECT_FALSE(fs::exists(shardStagingFolder(region / native)));

    auto wr = PyramidReader::open(whole / native);
    auto rr = PyramidReader::open(region / native);
    ASSERT_TRUE(wr) << wr.error().message;
    ASSERT_TRUE(rr) << rr.error().message;
    const PyramidManifest& wm = wr.value().manifest();
    const PyramidManifest& rm = rr.value().manifest();
    EXPECT_EQ(wr.value().layout().levelSamplesX(0), rr.value().layout().levelSamplesX(0));
    EXPECT_EQ(wr.value().layout().levelSamplesY(0), rr.value().layout().levelSamplesY(0));
    EXPECT_EQ(rm.georeference.originX, wm.georeference.originX);
    EXPECT_EQ(rm.georeference.originY, wm.georeference.originY);
    ASSERT_EQ(rm.levels.size(), wm.levels.size());
    const PyramidLayout& layout = wr.value().layout();
    // The margin's samples west and north of the source's.
    const Georeference& g = source.info().georeference;
    const auto west = static_cast<std::int64_t>(
        std::lround((g.originX - wm.georeference.originX) / g.pixelSizeX));
    const auto north = static_cast<std::int64_t>(
        std::lround((wm.georeference.originY - g.originY) / g.pixelSizeY));
    std::int64_t compared = 0;
    double largest = 0.0;
    for (int level = 0; level < layout.levelCount(); ++level)
        for (std::int64_t y = 0; y < layout.patchesY(level); ++y)
            for (std::int64_t x = 0; x < layout.patchesX(level); ++x) {
                const PatchId id{level, x, y};
                auto a = wr.value().readPatch(id);
                auto b = rr.value().readPatch(id);
                ASSERT_TRUE(a && b);
                ASSERT_EQ(a.value().heights.size(), b.value().heights.size());
                for (std::size_t i = 0; i < a.value().heights.size(); ++i)
                    largest = std::max(
                        largest, double(std::abs(a.value().heights[i] - b.value().heights[i])));
                for (std::size_t i = 0; i < a.value().heights.size(); ++i) {
                    // The source's own samples to the bit at the finest level.
                    const auto tile = static_cast<std::int64_t>(layout.tileSamples());
                    const std::int64_t column =
                        x * layout.patchQuads() + std::int64_t(i) % tile - 1 - west;
                    const std::int64_t row =
                        y * layout.patchQuads() + std::int64_t(i) / tile - 1 - north;
                    if (level == layout.finestLevel() && column >= 0 &&
                        column < source.info().width && row >= 0 && row < source.info().height) {
                        ASSERT_EQ(a.value().heights[i], b.value().heights[i])
                            << "level " << level << " (" << x << ", " << y << ") sample " << i;
                    }
                }
                EXPECT_NEAR(a.value().info.error, b.value().info.error, 1e-6);
                ++compared;
            }
    EXPECT_GT(compared, 0);
    ::testing::Test::RecordProperty("largestDifference", std::to_string(largest));
    // In the margin the whole build reads the composite's surface at each place, its edge
    // sample within a rounding (a float's of the weights, 6e-9 m here), the region build the
    // edge sample itself.
    EXPECT_LE(largest, 1e-6);
}

// Sea at 0 beside land (as SRTM's coasts): a 0 resampled at its own place is 0 only within
// a rounding (1e-12 m), which the native grid must not store in place of the sample.
TEST(GlobeShards, NativeGridOfARegionalSourceWithVoidsAndSea) {
    // SRTM's 3″ spacing, which no binary fraction holds, so the places round.
    const double pixel = 1.0 / 1200.0;
    GeographicFunctionDem source(
        11.0 - 0.5 * pixel, 57.2 + 0.5 * pixel, 300, 120, pixel, pixel, [](double lat, double lon) {
            const bool voidBlock = lat > 57.17 && lat < 57.18 && lon > 11.1 && lon < 11.12;
            const bool onTheEdge = lat < 57.16 && lon > 11.2 && lon < 11.21;
            if (voidBlock || onTheEdge) return std::numeric_limits<float>::quiet_NaN();
            return lon < 11.05 + 0.3 * (57.2 - lat) ? 0.0f : hills(lat, lon);
        });
    expectNativeGridMatchesWholeBuild(source);
}

TEST(GlobeShards, NativeGridOfAWholeEarthSource) {
    GeographicFunctionDem source(-181.0, 90.0, 181, 90, 2.0, 2.0, hills);
    expectNativeGridMatchesWholeBuild(source);
}

TEST(GlobeShards, StripAcrossTheAntimeridian) {
    GeographicFunctionDem source(179.8, -29.8, 80, 40, 0.005, 0.005, hills);
    expectRegionBuildMatchesWholeBuild(source, smallPatches());
}

TEST(GlobeShards, WholeEarthWithRepeatedSeamColumn) {
    GeographicFunctionDem source(-181.0, 90.0, 181, 90, 2.0, 2.0, hills);
    expectRegionBuildMatchesWholeBuild(source, smallPatches());
}

// Rows centred on the poles (grid-registered, as the built-in planet's): half a pixel beyond.
TEST(GlobeShards, GridRegisteredWholeEarth) {
    GeographicFunctionDem source(-181.0, 91.0, 181, 91, 2.0, 2.0, hills);
    expectRegionBuildMatchesWholeBuild(source, smallPatches());
}

// Voids longer than a block and a shard: each is filled from the row's valid samples beyond
// it, as the whole build fills the row.
TEST(GlobeShards, VoidsFillAcrossBlocksAndShards) {
    // A shard here is 64 face samples (~2.5 km), its blocks at most half its surroundings:
    // the long void crosses both, at 0.008° (~600 m) samples.
    GeographicFunctionDem source(10.0, 47.0, 250, 40, 0.008, 0.008, [](double lat, double lon) {
        const bool voidRun = lat > 46.85 && lat < 46.9 && lon > 10.1 && lon < 11.9;
        const bool voidBlock = lat > 46.75 && lat < 46.8 && lon > 10.5 && lon < 10.7;
        return voidRun || voidBlock ? std::numeric_limits<float>::quiet_NaN() : hills(lat, lon);
    });
    expectRegionBuildMatchesWholeBuild(source, smallPatches());
}

TEST(GlobeShards, LossyRegionBuildKeepsItsBounds) {
    GeographicFunctionDem source(8.0, 61.0, 200, 120, 0.01, 0.005, hills);
    PyramidBuildOptions options = smallPatches();
    options.maxErrorM = 2.0;
    expectRegionBuildMatchesWholeBuild(source, options);
}

TEST(GlobeShards, SharedEtopoBuildsByShardsAsWhole) {
    TERRAIN_SHARED_DATA_OR_SKIP(etopo, "etopo20_global.nc");
    auto reader = openDem({etopo.string()});
    ASSERT_TRUE(reader) << reader.error().message;
    PyramidBuildOptions options;
    options.threads = 2;
    // The level above the finest measured, the next nested from its intervals.
    expectRegionBuildMatchesWholeBuild(*reader.value(), options, 1);
}

// Every shard its own task, each level's in reverse order, then the merge: the same bytes as
// one process building them in order.
TEST(GlobeShards, TasksInAnotherOrderWriteTheSameBytes) {
    TempFolder temp;
    GeographicFunctionDem source(179.8, -29.8, 80, 40, 0.005, 0.005, hills);
    const PyramidBuildOptions options = smallPatches();
    const fs::path inOrder = temp.path() / "in-order.pyramid";
    ASSERT_TRUE(buildPyramidByShards(kGlobe, source, inOrder, options));
    const fs::path byTasks = temp.path() / "tasks.pyramid";
    auto plan = planPyramidShards(kGlobe, source, byTasks, options);
    ASSERT_TRUE(plan) << plan.error().message;
    int tasks = 0;
    for (int level = plan.value().layout.finestLevel(); level >= 0; --level) {
        const auto& shards = plan.value().shards[static_cast<std::size_t>(level)];
        for (auto s = shards.rbegin(); s != shards.rend(); ++s) {
            auto built = buildPyramidShard(kGlobe, source, byTasks, *s, options);
            ASSERT_TRUE(built) << built.error().message;
            // A task run again (a retried Dask task) rewrites the same bytes.
            if (tasks++ == 0) {
                ASSERT_TRUE(buildPyramidShard(kGlobe, source, byTasks, *s, options));
            }
        }
    }
    auto merged = mergePyramidShards(kGlobe, source, byTasks, options);
    ASSERT_TRUE(merged) << merged.error().message;
    EXPECT_EQ(pyramidFiles(inOrder), pyramidFiles(byTasks));
}

TEST(GlobeShards, MergeRefusesAMissingOrStaleShardAndWritesNothing) {
    TempFolder temp;
    GeographicFunctionDem source(179.8, -29.8, 80, 40, 0.005, 0.005, hills);
    const PyramidBuildOptions options = smallPatches();
    const fs::path out = temp.path() / "globe.pyramid";
    auto plan = planPyramidShards(kGlobe, source, out, options);
    ASSERT_TRUE(plan) << plan.error().message;
    const ShardPlan& p = plan.value();
    const int finest = p.layout.finestLevel();
    ASSERT_GE(p.shards[static_cast<std::size_t>(finest)].size(), 1u);
    // The parent of the first finest shard first: built without the shard beneath it.
    const ShardId child = p.shards[static_cast<std::size_t>(finest)].front();
    const ShardId parent{finest - 1, child.x / 2, child.y / 2};
    ASSERT_TRUE(buildPyramidShard(kGlobe, source, out, parent, options));
    for (int level = finest; level >= 0; --level)
        for (const ShardId& s : p.shards[static_cast<std::size_t>(level)])
            if (!(s == parent) && !(s == child)) {
                ASSERT_TRUE(buildPyramidShard(kGlobe, source, out, s, options));
            }
    auto missing = mergePyramidShards(kGlobe, source, out, options);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("missing"), std::string::npos)
        << missing.error().message;
    EXPECT_FALSE(fs::exists(out));
    ASSERT_TRUE(buildPyramidShard(kGlobe, source, out, child, options));
    auto stale = mergePyramidShards(kGlobe, source, out, options);
    ASSERT_FALSE(stale);
    EXPECT_NE(stale.error().message.find("was built before shard"), std::string::npos)
        << stale.error().message;
    EXPECT_FALSE(fs::exists(out));
    ASSERT_TRUE(buildPyramidShard(kGlobe, source, out, parent, options));
    EXPECT_TRUE(mergePyramidShards(kGlobe, source, out, options));
    EXPECT_TRUE(fs::exists(out / "manifest.json"));
}

TEST(GlobeShards, ASourceOverTheBudgetIsBuiltByShards) {
    TempFolder temp;
    GeographicFunctionDem source(-100.0, 88.0, 460, 440, 0.4, 0.4, hills);
    PyramidBuildOptions options = smallPatches();
    options.globeMeasuredLevels = 0;  // no level but the finest reads the source again
    auto plan = planPyramidShards(kGlobe, source, temp.path() / "plan.pyramid", options);
    ASSERT_TRUE(plan) << plan.error().message;
    // A whole build of 460 × 440 samples holds about 40 bytes a sample (and its finest face
    // level's patches): over the budget, which a shard fits. The samples' heights and masks
    // alone (5 bytes) fit half of it: what was counted before, which built it whole (1.2 GB
    // for a 3601² tile under --memory 1GiB).
    options.memoryBudgetBytes =
        std::max<std::uint64_t>(plan.value().taskBytes + (64 << 10), 2u * 460u * 440u * 5u);
    ASSERT_LT(options.memoryBudgetBytes, 460u * 440u * 40u);
    const fs::path small = temp.path() / "small.pyramid";
    auto built = buildGlobePyramid(source, small, options);
    ASSERT_TRUE(built) << built.error().message;
    ASSERT_FALSE(built.value().warnings.empty());
    EXPECT_NE(built.value().warnings.front().find("a whole globe build of its 460 × 440 samples "
                                                  "needs about"),
              std::string::npos)
        << built.value().warnings.front();
    const fs::path expected = temp.path() / "expected.pyramid";
    ASSERT_TRUE(buildPyramidByShards(kGlobe, source, expected, options));
    EXPECT_EQ(pyramidFiles(small), pyramidFiles(expected));
}

// Sources composited together are built whole, so a composite whose whole build would hold
// more than --memory is refused, naming the first source and the remedy, as a planar build
// too wide for it is; nothing is left behind (built within the budget before, and over it).
TEST(GlobeShards, SourcesCompositedOverTheBudgetAreRefused) {
    TempFolder temp;
    GeographicFunctionDem coarse(0.0, 70.0, 200, 100, 0.5, 0.5, hills);
    GeographicFunctionDem fine(10.0, 61.0, 300, 200, 0.01, 0.005, hills);
    DemReader* const sources[] = {&fine, &coarse};
    PyramidBuildOptions options = smallPatches();
    options.memoryBudgetBytes = 1u << 20;  // the fine source's 60,000 samples alone hold 2.3 MB
    const fs::path out = temp.path() / "composite.pyramid";
    auto refused = buildGlobePyramid(sources, out, options);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("a whole globe build of its 2 sources needs about"),
              std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("more than --memory (1 MiB); raise --memory"),
              std::string::npos)
        << refused.error().message;
    EXPECT_FALSE(fs::exists(out));
    options.memoryBudgetBytes = std::uint64_t{64} << 20;
    EXPECT_TRUE(buildGlobePyramid(sources, out, options));
}

// Measured at the source's samples (the default for a source this small, and for the two
// levels above the finest of any): the whole build's files, byte for byte.
TEST(GlobeShards, MeasuredLevelsAreTheWholeBuildsBytes) {
    TempFolder temp;
    GeographicFunctionDem source(8.0, 61.0, 300, 200, 0.01, 0.005, hills);
    const fs::path whole = temp.path() / "whole.pyramid";
    ASSERT_TRUE(buildGlobePyramid(source, whole, smallPatches()));
    const fs::path region = temp.path() / "region.pyramid";
    ASSERT_TRUE(buildPyramidByShards(kGlobe, source, region, smallPatches()));
    EXPECT_EQ(pyramidFiles(whole), pyramidFiles(region));
}

// Oversampled (PyramidBuildOptions::globeOversampleLevels): the region build goes as far below
// the source as the whole build, with the same patches and tiles, and says so in its manifest.
TEST(GlobeShards, OversampledRegionBuildMatchesWholeBuild) {
    GeographicFunctionDem source(8.0, 61.0, 60, 40, 0.01, 0.005, hills);
    PyramidBuildOptions options = smallPatches();
    options.globeOversampleLevels = 1;
    expectRegionBuildMatchesWholeBuild(source, options);
    TempFolder temp;
    auto r = buildPyramidByShards(kGlobe, source, temp.path() / "r.pyramid", options);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r.value().manifest.globe->oversampleLevels, 1);
}

TEST(GlobeShards, ShardsOfAnotherPlanAndForeignShardsAreRefused) {
    TempFolder temp;
    GeographicFunctionDem source(179.8, -29.8, 80, 40, 0.005, 0.005, hills);
    const fs::path out = temp.path() / "globe.pyramid";
    ASSERT_TRUE(planPyramidShards(kGlobe, source, out, smallPatches()));
    // Another compression, another oversampling: not the plan's shards.
    PyramidBuildOptions otherCompression = smallPatches();
    otherCompression.compressionLevel = 3;
    PyramidBuildOptions otherOversampling = smallPatches();
    otherOversampling.globeOversampleLevels = 1;
    for (const PyramidBuildOptions& other : {otherCompression, otherOversampling}) {
        auto refused = buildPyramidShard(kGlobe, source, out, ShardId{3, 0, 0}, other);
        ASSERT_FALSE(refused);
        EXPECT_NE(refused.error().message.find("another source or with other options"),
                  std::string::npos)
            << refused.error().message;
    }
    auto nowhere = buildPyramidShard(kGlobe, source, out, ShardId{0, 0, 0}, smallPatches());
    ASSERT_FALSE(nowhere);
    EXPECT_NE(nowhere.error().message.find("is not one of this globe pyramid's"), std::string::npos)
        << nowhere.error().message;
}

}  // namespace
}  // namespace terrain::io
