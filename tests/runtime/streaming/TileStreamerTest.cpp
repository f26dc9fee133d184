// runtime::TileStreamer end to end, with the real I/O thread and GPU pool on a real
// context, driven by runtime::selectPatches: the root arrives first, every drawn patch is
// resident on its layer of the pool, drawn and culled patches tile the domain even with
// tiny budgets, injected latency and injected faults; faults are reported once, naming
// the shard file, and their ancestors keep drawing; every request ends once; telemetry
// counts every frame. Frames wait for the I/O thread's outcomes (waitForReads), never
// sleep, and no assertion counts on how fast the thread reads. The selection's own rules
// are tested without threads or GL in tests/runtime/lod/PatchSelectionTest.cpp.
#include "GlTestFixture.h"
#include "GlobeTestSources.h"
#include "StreamingTestPyramid.h"
#include "TempFolder.h"
#include "TestCameras.h"
#include "terrain/cache/TileCache.h"
#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TileStreamer.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <unordered_set>
#include <vector>

namespace terrain::test {
namespace {

using runtime::Camera;
using runtime::PatchDraw;
using runtime::PatchSelectionStats;
using runtime::TileStreamer;

class TileStreamerTest : public GlTest {
protected:
    static std::unique_ptr<TileStreamer> open(const runtime::TileStreamerOptions& options) {
        auto opened = TileStreamer::open(streamingTestPyramid(), options);
        EXPECT_TRUE(opened) << opened.error().message;
        return opened ? std::move(opened).value() : nullptr;
    }

    static Camera lowOblique(const runtime::TerrainGeometry& g) {
        return cameraOverDem(g, 0.3, 0.2, 200.0, 0.6, 0.7);
    }

    struct Frame {
        std::vector<PatchDraw> draws;
        PatchSelectionStats stats;
    };

    /// One frame: select, check what a draw would reference, end the frame.
    static void frame(TileStreamer& s, const runtime::TerrainGeometry& g, const Camera& c,
                      double errorPx, Frame& f) {
        s.beginFrame();
        f.stats = runtime::selectPatches(c, g, errorPx, s, f.draws);
        runtime::FrameTelemetry t;
        s.endFrame(t);
    }

    /// Drawn patches are resident on their layers and, with the culled ones, cover every
    /// finest-level patch exactly once.
    static void expectCoverage(const TileStreamer& s, const Frame& f) {
        const std::uint64_t domain = runtime::finestPatchesCovered(s.layout(), {0, 0, 0});
        EXPECT_EQ(f.stats.coveredFinestPatches, domain);
        std::unordered_set<io::PatchId, io::PatchIdHash> drawn;
        for (const PatchDraw& d : f.draws) {
            EXPECT_TRUE(s.pool().isResident(d.id));
            EXPECT_EQ(s.pool().patchOnLayer(d.layer), std::optional<io::PatchId>(d.id));
            EXPECT_TRUE(drawn.insert(d.id).second);
        }
        for (const PatchDraw& d : f.draws) {
            for (io::PatchId up = d.id; up.level > 0;) {
                up = {up.level - 1, up.x / 2, up.y / 2};
                EXPECT_FALSE(drawn.contains(up)) << "a drawn patch overlaps an ancestor";
            }
        }
        EXPECT_EQ(s.checkInvariants(), std::nullopt);
    }
};

TEST_F(TileStreamerTest, SettlesOnAResidentCoverOfTheView) {
    auto s = open({});
    ASSERT_TRUE(s);
    const runtime::TerrainGeometry g(s->manifest());
    const Camera c = lowOblique(g);
    Frame f;
    frame(*s, g, c, 1.0, f);
    EXPECT_TRUE(f.draws.empty()) << "nothing can draw before the root arrives";
    bool settled = false;
    // Each frame waits for a read's outcome, so the frames it takes are bounded by the
    // reads the view needs (a few dozen), not by time.
    for (int i = 0; i < 400 && !settled; ++i) {
        frame(*s, g, c, 1.0, f);
        settled = !f.draws.empty() && f.stats.waitingSplits == 0 && s->loadsOutstanding() == 0;
        if (!settled) s->waitForReads(std::chrono::milliseconds(100));
    }
    ASSERT_TRUE(settled) << "the view never settled";
    expectCoverage(*s, f);
    EXPECT_GT(f.draws.size(), 4u);
    EXPECT_GT(f.stats.culled, 0u) << "the oblique view sees only part of the DEM";
    const int levels = s->layout().levelCount();
    int finest = 0;
    for (const PatchDraw& d : f.draws) finest = std::max(finest, d.id.level);
    EXPECT_EQ(finest, levels - 1) << "a low view at 1 px needs the finest level somewhere";

    // A static camera changes nothing once settled.
    const std::vector<PatchDraw> before = f.draws;
    const auto requested = s->ledger().submitted;
    frame(*s, g, c, 1.0, f);
    EXPECT_EQ(s->ledger().submitted, requested);
    ASSERT_EQ(f.draws.size(), before.size());
    for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(f.draws[i].id, before[i].id);
    EXPECT_TRUE(s->drain(std::chrono::seconds(10)));
}

TEST_F(TileStreamerTest, TinyBudgetsSlowReadsAndFaultsEndEveryRequestOnce) {
    runtime::TileStreamerOptions o;
    o.gpuLayers = 12;
    o.cpuCacheBytes = 6 * 5000;  // a handful of 35² tiles
    o.uploadBytesPerFrame = 1;   // one upload per frame
    o.io.faults = {.errorRate = 0.2, .addedLatencyMs = 1.0, .seed = 7};
    auto s = open(o);
    ASSERT_TRUE(s);
    const runtime::TerrainGeometry g(s->manifest());
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Camera c = lowOblique(g);
    Frame f;
    std::uint64_t framesDrawn = 0;
    for (int i = 0; i < 600; ++i) {
        if (i % 20 == 0) {  // teleport
            const double fx = u(random), fy = u(random);
            c.position = {g.worldAtFraction(fx, fy), g.maxHeight() + 10.0 + 2000.0 * u(random)};
            const double tx = u(random), ty = u(random);
            c.lookAt({g.worldAtFraction(tx, ty), g.minHeight()});
        }
        frame(*s, g, c, 0.5, f);
        s->waitForReads(std::chrono::milliseconds(50));  // a read's worth of time
        if (f.stats.visited == 0) continue;              // the root is not in yet
        ++framesDrawn;
        ASSERT_NO_FATAL_FAILURE(expectCoverage(*s, f));
        for (const PatchDraw& d : f.draws) EXPECT_FALSE(s->hasFailed(d.id));
    }
    EXPECT_GT(framesDrawn, 0u) << "the root never arrived";
    ASSERT_TRUE(s->drain(std::chrono::seconds(10)));
    const runtime::TileRequestLedger& ledger = s->ledger();
    EXPECT_EQ(ledger.submitted, ledger.completed + ledger.cancelled + ledger.failed);
    const io::IoThreadStats io = s->ioStats();
    EXPECT_EQ(io.requested, ledger.submitted);
    EXPECT_GT(ledger.failed, 0u) << "a 20% fault rate over hundreds of reads fails some";
    EXPECT_EQ(io.injectedFaults, ledger.failed);
    // Each fault is reported once, names its patch, and is never requested again.
    std::unordered_set<io::PatchId, io::PatchIdHash> reported;
    for (const runtime::TileFault& fault : s->faults()) {
        EXPECT_TRUE(reported.insert(fault.id).second);
        EXPECT_NE(fault.message.find("injected fault"), std::string::npos) << fault.message;
        EXPECT_TRUE(o.io.faults.failsRead(fault.id));
    }
    // A patch may fail more than once (a cancel, then a new request of it, both reading
    // it), but it is reported once.
    EXPECT_LE(reported.size(), ledger.failed);
    EXPECT_GT(reported.size(), 0u);
}

// A real fault: a finest-level shard file is missing. Each of its patches is reported once,
// naming the shard file, and the area keeps being drawn by resident ancestors.
TEST_F(TileStreamerTest, MissingShardIsReportedOncePerPatchAndAncestorsDraw) {
    TempFolder folder;
    const std::filesystem::path copy = folder.path() / "damaged.pyramid";
    std::filesystem::copy(streamingTestPyramid(), copy, std::filesystem::copy_options::recursive);
    auto manifest = io::readManifest(copy);
    ASSERT_TRUE(manifest) << manifest.error().message;
    const io::PyramidLayout& layout = manifest.value().layout;
    const io::ShardId lost{layout.finestLevel(), 0, 0};
    const std::filesystem::path shard = copy / layout.shardPath(lost);
    ASSERT_TRUE(std::filesystem::remove(shard)) << shard;

    auto opened = TileStreamer::open(copy, {});
    ASSERT_TRUE(opened) << opened.error().message;
    TileStreamer& s = *opened.value();
    const runtime::TerrainGeometry g(s.manifest());
    // Low over the north-west corner, where the lost shard lies, looking down.
    const Camera c = cameraOverDem(g, 0.05, 0.05, 50.0, 0.1, 0.1);
    Frame f;
    for (int i = 0; i < 400; ++i) {
        frame(s, g, c, 0.5, f);
        if (f.stats.visited > 0) {
            ASSERT_NO_FATAL_FAILURE(expectCoverage(s, f));
        }
        if (f.stats.waitingSplits == 0 && s.loadsOutstanding() == 0 && i > 0) break;
        s.waitForReads(std::chrono::milliseconds(100));
    }
    ASSERT_FALSE(s.faults().empty()) << "the view needs patches of the lost shard";
    std::unordered_set<io::PatchId, io::PatchIdHash> reported;
    for (const runtime::TileFault& fault : s.faults()) {
        EXPECT_TRUE(reported.insert(fault.id).second) << "reported twice";
        EXPECT_EQ(layout.shardOf(fault.id), lost);
        EXPECT_NE(fault.message.find(shard.filename().string()), std::string::npos)
            << fault.message;
    }
    for (const PatchDraw& d : f.draws) {
        EXPECT_FALSE(d.id.level == lost.level && layout.shardOf(d.id) == lost)
            << "a patch of the lost shard is drawn";
    }
    EXPECT_GT(f.draws.size(), 0u);
    EXPECT_TRUE(s.drain(std::chrono::seconds(10)));
    EXPECT_GE(s.ledger().failed, s.faults().size());
}

// Shards that change under a running streamer, as a sync tool or a user's cleanup does it:
// after the whole DEM was drawn from afar, every finest-level shard is deleted or replaced
// (by rename, as a sync does) with bytes that are not a shard. Flying low over every part
// of the DEM then fails those reads: each is a fault naming its shard, reported once, the
// area is drawn by ancestors, and the streamer's invariants hold every frame.
TEST_F(TileStreamerTest, ShardsDeletedOrReplacedWhileStreamingAreFaults) {
    TempFolder folder;
    const std::filesystem::path copy = folder.path() / "changing.pyramid";
    std::filesystem::copy(streamingTestPyramid(), copy, std::filesystem::copy_options::recursive);
    auto opened = TileStreamer::open(copy, {});
    ASSERT_TRUE(opened) << opened.error().message;
    TileStreamer& s = *opened.value();
    const runtime::TerrainGeometry g(s.manifest());
    const io::PyramidLayout& layout = s.layout();
    const auto settle = [&](const Camera& c) {
        Frame f;
        for (int i = 0; i < 400; ++i) {
            frame(s, g, c, 1.0, f);
            if (f.stats.visited > 0) {
                ASSERT_NO_FATAL_FAILURE(expectCoverage(s, f));
            }
            // Settled: nothing more will arrive (a split waiting on a failed child waits
            // for good; its patch stays drawn).
            if (s.loadsOutstanding() == 0 && i > 0) return;
            s.waitForReads(std::chrono::milliseconds(100));
        }
        ADD_FAILURE() << "did not settle: " << f.stats.waitingSplits << " splits waiting, "
                      << s.loadsOutstanding() << " loads outstanding, " << f.draws.size()
                      << " drawn, " << s.faults().size() << " faults";
    };
    settle(cameraOverDem(g, 0.5, 0.5, 4.0 * g.demSize().x, 0.5, 0.55));
    ASSERT_TRUE(s.faults().empty());

    const int finest = layout.finestLevel();
    int changed = 0;
    for (std::int64_t y = 0; y < layout.shardsY(finest); ++y) {
        for (std::int64_t x = 0; x < layout.shardsX(finest); ++x) {
            const std::filesystem::path shard = copy / layout.shardPath({finest, x, y});
            if (!std::filesystem::exists(shard)) continue;
            if ((x + y) % 2 == 0) {
                std::filesystem::remove(shard);
            } else {
                const std::filesystem::path fresh = shard.string() + ".sync-tmp";
                std::ofstream(fresh, std::ios::binary) << "a half-synced file, not a shard";
                std::filesystem::rename(fresh, shard);
            }
            ++changed;
        }
    }
    ASSERT_GT(changed, 0);
    for (const double fx : {0.1, 0.5, 0.9})
        for (const double fy : {0.1, 0.5, 0.9})
            ASSERT_NO_FATAL_FAILURE(settle(cameraOverDem(g, fx, fy, 30.0, fx + 0.05, fy + 0.05)));

    ASSERT_FALSE(s.faults().empty()) << "the low views need finest patches";
    std::unordered_set<io::PatchId, io::PatchIdHash> reported;
    for (const runtime::TileFault& fault : s.faults()) {
        EXPECT_TRUE(reported.insert(fault.id).second) << "reported twice";
        EXPECT_EQ(fault.id.level, finest) << fault.message;
        EXPECT_NE(fault.message.find(".exr"), std::string::npos) << fault.message;
    }
    EXPECT_TRUE(s.drain(std::chrono::seconds(10)));
}

// A CPU cache too small for one tile would never let a tile reach the GPU, and the terrain
// would never draw: opening the pyramid says so instead.
TEST_F(TileStreamerTest, APrefetchedTileWaitsInTheCpuCacheAndIsUploadedWhenWanted) {
    const io::PatchId id{2, 1, 1};
    auto s = open({});
    ASSERT_TRUE(s);
    runtime::FrameTelemetry t;
    // Asked for ahead every frame (as the LOD does while it waits), until it is read.
    for (int i = 0; i < 400 && !s->cpuCache().contains(id); ++i) {
        s->beginFrame();
        s->prefetch(id, 1.0f);
        s->endFrame(t);
        if (!s->cpuCache().contains(id)) s->waitForReads(std::chrono::milliseconds(100));
    }
    s->beginFrame();  // takes the last read
    ASSERT_TRUE(s->cpuCache().contains(id)) << "the prefetch was never read";
    EXPECT_FALSE(s->pool().isResident(id)) << "a prefetch reads into the CPU cache only";
    EXPECT_EQ(s->ledger().submitted, 1u);
    // Wanted now: uploaded at once from the CPU cache, with no second read.
    const io::PatchInfo* info = s->acquire(id, 1.0f);
    s->endFrame(t);
    EXPECT_NE(info, nullptr);
    EXPECT_TRUE(s->pool().isResident(id));
    EXPECT_EQ(s->ledger().submitted, 1u);
    EXPECT_TRUE(s->drain(std::chrono::seconds(10)));

    // Turned off (--no-prefetch): nothing is read ahead.
    runtime::TileStreamerOptions noPrefetch;
    noPrefetch.prefetch = false;
    auto off = open(noPrefetch);
    ASSERT_TRUE(off);
    off->beginFrame();
    off->prefetch(id, 1.0f);
    off->endFrame(t);
    EXPECT_EQ(off->ledger().submitted, 0u);
    EXPECT_EQ(t.requestsMade, 0u);
}

TEST_F(TileStreamerTest, AnAbsentPatchReadAheadIsKnownAbsentNotAFault) {
    // The sparse globe: the LOD reads ahead patches whose presence only their parent knows
    // (issue 49). One the pyramid does not store ends known absent, is never read again, and
    // is no fault; asked for as stored (acquire), it is one, as a failed read was before.
    TempFolder folder;
    const std::filesystem::path pyramid = folder.path() / "regional.pyramid";
    GeographicFunctionDem source(10.0, 60.25, 100, 50, 0.005, 0.005, hills);
    auto built = io::buildGlobePyramid(source, pyramid, smallGlobePatches());
    ASSERT_TRUE(built) << built.error().message;
    auto reader = io::PyramidReader::open(pyramid);
    ASSERT_TRUE(reader) << reader.error().message;
    // Absent patches one level below the face roots: in a shard that stores a patch, and in
    // one the pyramid has no file for.
    const io::PyramidLayout& layout = reader.value().layout();
    const int level = io::ManifestGlobe::kLevelOffset + 1;
    std::vector<io::PatchId> present, absent;
    for (std::int64_t y = 0; y < layout.patchesY(level); ++y)
        for (std::int64_t x = 0; x < layout.patchesX(level); ++x) {
            const io::PatchId id{level, x, y};
            auto info = reader.value().patchInfo(id);
            ASSERT_TRUE(info) << info.error().message;
            (info.value().present ? present : absent).push_back(id);
        }
    ASSERT_FALSE(present.empty());
    std::vector<io::PatchId> chosen;
    const auto inStoredShard = [&](const io::PatchId& id) {
        return std::any_of(present.begin(), present.end(), [&](const io::PatchId& p) {
            return layout.shardOf(p) == layout.shardOf(id);
        });
    };
    for (const bool stored : {true, false}) {
        const auto it = std::find_if(absent.begin(), absent.end(), [&](const io::PatchId& id) {
            return inStoredShard(id) == stored;
        });
        if (it != absent.end()) chosen.push_back(*it);
    }
    ASSERT_FALSE(chosen.empty());

    auto opened = TileStreamer::open(pyramid, {});
    ASSERT_TRUE(opened) << opened.error().message;
    TileStreamer& s = *opened.value();
    runtime::FrameTelemetry t;
    const auto allKnown = [&] {
        return std::all_of(chosen.begin(), chosen.end(),
                           [&](const io::PatchId& id) { return s.knownAbsent(id); });
    };
    for (int i = 0; i < 400 && !allKnown(); ++i) {
        s.beginFrame();
        for (const io::PatchId& id : chosen) s.prefetch(id, 1.0f);
        s.endFrame(t);
        if (!allKnown()) s.waitForReads(std::chrono::milliseconds(100));
    }
    ASSERT_TRUE(allKnown()) << "the reads ahead never ended";
    EXPECT_TRUE(s.faults().empty()) << s.faults().front().message;
    const std::uint64_t submitted = s.ledger().submitted;
    EXPECT_EQ(submitted, chosen.size());
    // Known absent: not read again.
    s.beginFrame();
    for (const io::PatchId& id : chosen) s.prefetch(id, 1.0f);
    s.endFrame(t);
    EXPECT_EQ(s.ledger().submitted, submitted);
    // Asked for as stored: read once more, and a fault naming the shard file and the patch.
    const io::PatchId wanted = chosen.front();
    for (int i = 0; i < 400 && !s.hasFailed(wanted); ++i) {
        s.beginFrame();
        EXPECT_EQ(s.acquire(wanted, 1.0f), nullptr);
        s.endFrame(t);
        if (!s.hasFailed(wanted)) s.waitForReads(std::chrono::milliseconds(100));
    }
    ASSERT_TRUE(s.hasFailed(wanted));
    ASSERT_EQ(s.faults().size(), 1u);
    const std::string& fault = s.faults().front().message;
    EXPECT_NE(fault.find("absent"), std::string::npos) << fault;
    EXPECT_NE(fault.find(reader.value().shardFile(wanted).filename().string()), std::string::npos)
        << fault;
    EXPECT_EQ(s.ledger().submitted, submitted + 1);
    EXPECT_EQ(s.ledger().failed, 1u) << "the contradiction counts as a failed read";
    EXPECT_EQ(s.ledger().completed, submitted);
    EXPECT_TRUE(s.drain(std::chrono::seconds(10)));
    EXPECT_EQ(s.ledger().ended(), s.ledger().submitted);
    EXPECT_EQ(s.checkInvariants(), std::nullopt);
}

TEST_F(TileStreamerTest, ACpuCacheThatHoldsNoTileIsRefused) {
    const io::PyramidManifest& manifest = streamingTestManifest();
    const std::size_t tileBytes =
        cache::TileCache::tileBytes(manifest.layout, manifest.noData.present);
    runtime::TileStreamerOptions o;
    o.cpuCacheBytes = tileBytes - 1;
    auto refused = TileStreamer::open(streamingTestPyramid(), o);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find(streamingTestPyramid().string()), std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("holds no tile"), std::string::npos)
        << refused.error().message;
    o.cpuCacheBytes = tileBytes;
    EXPECT_TRUE(TileStreamer::open(streamingTestPyramid(), o));
}

TEST_F(TileStreamerTest, TelemetryCountsTheFrame) {
    auto s = open({});
    ASSERT_TRUE(s);
    const runtime::TerrainGeometry g(s->manifest());
    const Camera c = lowOblique(g);
    std::vector<PatchDraw> draws;
    runtime::FrameTelemetry sum;
    std::uint64_t frames = 0, residentTotal = 0;
    for (int i = 0; i < 400; ++i) {
        s->beginFrame();
        runtime::selectPatches(c, g, 1.0, *s, draws);
        runtime::FrameTelemetry t;
        s->endFrame(t);
        ++frames;
        sum.requestsMade += t.requestsMade;
        sum.requestsCompleted += t.requestsCompleted;
        sum.gpuUploads += t.gpuUploads;
        sum.diskReadBytes += t.diskReadBytes;
        residentTotal += t.loadsResident;
        EXPECT_EQ(t.gpuLayersUsed + t.gpuLayersFree,
                  static_cast<std::uint64_t>(s->pool().capacity()));
        EXPECT_LE(t.cpuCacheBytes, t.cpuCacheBudgetBytes);
        if (i > 0 && s->loadsOutstanding() == 0) break;
        s->waitForReads(std::chrono::milliseconds(100));
    }
    EXPECT_EQ(sum.requestsMade, s->ledger().submitted);
    EXPECT_EQ(sum.requestsCompleted, s->ledger().completed);
    EXPECT_EQ(sum.gpuUploads, static_cast<std::uint64_t>(s->pool().layersUsed()));
    EXPECT_EQ(residentTotal, s->loadLatencies().count());
    EXPECT_GE(sum.diskReadBytes, sum.requestsCompleted * 33u * 33u * sizeof(float));
}

/// Half of level 3 (8 × 8 patches): more tiles than the I/O options' default cap of 8.
std::vector<io::PatchId> halfOfLevel3() {
    std::vector<io::PatchId> wanted;
    for (std::int64_t y = 0; y < 4; ++y)
        for (std::int64_t x = 0; x < 8; ++x) wanted.push_back({3, x, y});
    return wanted;
}

/// One frame that requests `wanted`, then waits between frames until the I/O side has read
/// everything (or, when it waits for poll() with reads left, until the bound, which only
/// ends a wait that cannot end otherwise).
void requestAndWaitForReads(TileStreamer& s, const std::vector<io::PatchId>& wanted) {
    runtime::FrameTelemetry t;
    s.beginFrame();
    for (const io::PatchId& id : wanted) EXPECT_EQ(s.acquire(id, 1.0f), nullptr);
    s.endFrame(t);
    EXPECT_EQ(t.requestsMade, wanted.size());
    const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < giveUp) {
        const io::IoThreadStats io = s.ioStats();
        if (io.queueDepth + io.inFlight == 0) break;
        s.waitForReads(std::chrono::milliseconds(100));
    }
}

TEST_F(TileStreamerTest, AFrameTakesAsManyFinishedReadsAsItsUploadBudgetHolds) {
    // Issue 49: with the I/O side's results capped at a tile count (8), a frame that came
    // after many finished reads made at most 8 resident. One reader thread and the default
    // cap of the I/O options: the streamer raises it to its upload budget in tiles.
    runtime::TileStreamerOptions o;
    o.io.readerThreads = 1;
    ASSERT_EQ(o.io.maxUnpolled, 8U);
    auto s = open(o);
    ASSERT_TRUE(s);
    const std::vector<io::PatchId> wanted = halfOfLevel3();
    ASSERT_GT(wanted.size(), 2 * o.io.maxUnpolled);
    ASSERT_LE(wanted.size() * s->pool().uploadBytesPerTile(), o.uploadBytesPerFrame);

    requestAndWaitForReads(*s, wanted);
    runtime::FrameTelemetry t;
    s->beginFrame();
    for (const io::PatchId& id : wanted) EXPECT_NE(s->acquire(id, 1.0f), nullptr) << id.x;
    s->endFrame(t);
    EXPECT_EQ(t.requestsCompleted, wanted.size());
    EXPECT_EQ(t.loadsResident, wanted.size());
    EXPECT_EQ(s->checkInvariants(), std::nullopt);
    EXPECT_TRUE(s->drain(std::chrono::seconds(10)));
}

TEST_F(TileStreamerTest, AnUploadTimeBudgetStillUploadsOneTileAFrame) {
    // A budget no upload fits in (a picosecond): every frame uploads one tile, the first,
    // and defers the rest; the byte budget alone would take them all at once.
    runtime::TileStreamerOptions o;
    o.uploadMsPerFrame = 1e-9;
    auto s = open(o);
    ASSERT_TRUE(s);
    const std::vector<io::PatchId> wanted = halfOfLevel3();
    requestAndWaitForReads(*s, wanted);
    std::size_t frames = 0, resident = 0;
    while (resident < wanted.size() && frames < 2 * wanted.size()) {
        runtime::FrameTelemetry t;
        s->beginFrame();
        for (const io::PatchId& id : wanted) s->acquire(id, 1.0f);
        s->endFrame(t);
        ++frames;
        EXPECT_EQ(t.loadsResident, 1U) << "frame " << frames;
        EXPECT_EQ(t.gpuUploadsDeferred, wanted.size() - resident - 1) << "frame " << frames;
        resident += t.loadsResident;
    }
    EXPECT_EQ(resident, wanted.size());
    EXPECT_EQ(frames, wanted.size());
    EXPECT_EQ(s->checkInvariants(), std::nullopt);
    EXPECT_TRUE(s->drain(std::chrono::seconds(10)));
}

}  // namespace
}  // namespace terrain::test
