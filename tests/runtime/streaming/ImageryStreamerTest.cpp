// runtime::ImageryStreamer through TileStreamer, with the real I/O thread, a fake imagery
// source and the GPU imagery pool on a real context: a wanted tile becomes resident within
// a bounded number of frames (each waiting on the I/O thread's outcome, never sleeping) with
// its source's texels; an absent tile is known and never uploaded; requests wanted by no
// frame for cancelAfterFrames frames are cancelled and others are not; a failing tile (and a
// layer that cannot be opened) is reported once and never asked for again; a tiny GPU budget
// evicts only tiles the frame does not use; every request ends once; telemetry counts it;
// warm frames that evict and re-upload from the CPU cache allocate nothing.
#include "AllocationCounter.h"
#include "FakeImagerySource.h"
#include "GlTestFixture.h"
#include "TempFolder.h"
#include "TinyPyramid.h"
#include "terrain/cache/ImageryTilePool.h"
#include "terrain/runtime/ImageryStreamer.h"
#include "terrain/runtime/TileStreamer.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <vector>

namespace terrain::test {
namespace {

using namespace std::chrono_literals;
using runtime::FrameTelemetry;
using runtime::ImageryStreamer;
using runtime::TileStreamer;

// Only turns a hung I/O thread into a failure; no assertion depends on time.
constexpr std::chrono::milliseconds kHangTimeout = 120s;

class ImageryStreamerTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        auto manifest = writeTinyPyramid(m_dir.path(), {});
        ASSERT_TRUE(manifest.ok()) << manifest.error().message;
        ASSERT_TRUE(addImageryLayers(m_dir.path(), 2).ok());
    }

    std::unique_ptr<TileStreamer> open(
        const FakeImageryRules& rules, int gpuTiles = 8, std::uint32_t failToOpen = 0,
        double latencyMs = 0.0,
        std::size_t cpuCacheBytes = 16 * cache::ImageryTileCache::kPresentTileBytes) {
        runtime::TileStreamerOptions options;
        options.gpuLayers = 16;
        options.io.openImagery = fakeImageryOpener(rules, failToOpen);
        options.io.faults.addedLatencyMs = latencyMs;
        options.imagery.gpuBytes =
            cache::ImageryTilePool::bytesPerLayer() * static_cast<std::size_t>(gpuTiles);
        options.imagery.cpuCacheBytes = cpuCacheBytes;
        options.imagery.uploadBytesPerFrame = 2 * cache::ImageryTilePool::bytesPerLayer();
        options.imagery.cancelAfterFrames = 3;
        auto opened = TileStreamer::open(m_dir.path(), options);
        EXPECT_TRUE(opened) << (opened ? "" : opened.error().message);
        return opened ? std::move(opened).value() : nullptr;
    }

    /// One frame: the body plays the draw's selection; telemetry summed into m_sum.
    FrameTelemetry frame(TileStreamer& s, const std::function<void(ImageryStreamer&)>& body) {
        s.beginFrame();
        body(s.imagery());
        FrameTelemetry t;
        s.endFrame(t);
        EXPECT_EQ(s.checkInvariants(), std::nullopt);
        runtime::addStreamingCounts(m_sum, t);
        return t;
    }

    static std::vector<std::uint8_t> readLayer(const TileStreamer& s, int layer) {
        std::vector<std::uint8_t> texels(io::kImageryTileBytes);
        s.imageryTiles().readBack(
            {.layer = layer, .width = io::kImageryTileTexels, .height = io::kImageryTileTexels},
            GL_RGBA, GL_UNSIGNED_BYTE, std::as_writable_bytes(std::span(texels)));
        return texels;
    }

    TempFolder m_dir;
    FrameTelemetry m_sum;  // the frame-scope counts of every frame
};

TEST_F(ImageryStreamerTest, AWantedTileBecomesResidentWithItsTexels) {
    auto s = open({});
    ASSERT_TRUE(s);
    EXPECT_EQ(s->imagery().imageryLayerCount(), 2);
    ASSERT_TRUE(s->imageryTiles().valid());
    const io::PatchId id{1, 1, 0};
    std::optional<int> layer;
    int frames = 0;
    // Frame 1 asks; the read ends; frame 2 takes it into the CPU cache and uploads it.
    for (; frames < 4 && !layer; ++frames) {
        frame(*s, [&](ImageryStreamer& imagery) {
            layer = imagery.gpuLayer(1, id);
            if (!layer) imagery.want(1, id, 2.0f);
            layer = imagery.gpuLayer(1, id);
        });
        if (!layer) {
            ASSERT_TRUE(s->waitForReads(kHangTimeout));
        }
    }
    ASSERT_TRUE(layer) << "not resident after " << frames << " frames";
    EXPECT_LE(frames, 2);
    io::ImageryTile expected;
    fillFakeImagery(1, id, io::kImageryTileBytes, expected);
    EXPECT_EQ(readLayer(*s, *layer), expected.rgba);
    const io::ImageryTileInfo* info = s->imagery().tileInfo(1, id);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(*info, expected.info);
    EXPECT_EQ(s->imagery().tileInfo(0, id), nullptr) << "another layer's tile: never read";

    // Resident: wanting it again asks nothing.
    const FrameTelemetry t = frame(*s, [&](ImageryStreamer& imagery) {
        imagery.want(1, id, 5.0f);
        EXPECT_EQ(imagery.gpuLayer(1, id), layer);
    });
    EXPECT_EQ(t.imageryTilesResident, 1U);
    EXPECT_EQ(t.imageryGpuBytes, cache::ImageryTilePool::bytesPerLayer());
    EXPECT_EQ(t.imageryRequestsPending, 0U);
    EXPECT_EQ(m_sum.imageryRequestsMade, 1U);
    EXPECT_EQ(m_sum.imageryRequestsCompleted, 1U);
    EXPECT_EQ(m_sum.imageryLoadsResident, 1U);
    EXPECT_EQ(m_sum.imageryGpuUploads, 1U);
    EXPECT_FALSE(std::isnan(t.imageryLoadLatencyP50Ms));
    EXPECT_EQ(m_sum.requestsMade, 0U) << "imagery requests are not the heights'";
    EXPECT_EQ(s->imagery().loadsOutstanding(), 0U);
    EXPECT_TRUE(s->drain(10s));
}

TEST_F(ImageryStreamerTest, AnAbsentTileIsKnownAndNeverUploaded) {
    FakeImageryRules rules;
    rules.absent = [](int, const io::PatchId& id) { return id.level == 2; };
    auto s = open(rules);
    ASSERT_TRUE(s);
    const io::PatchId id{2, 3, 1};
    for (int f = 0; f < 5; ++f) {
        frame(*s, [&](ImageryStreamer& imagery) {
            imagery.want(0, id, 1.0f);
            EXPECT_EQ(imagery.gpuLayer(0, id), std::nullopt);
        });
        if (s->imagery().requestsLive() > 0) {
            ASSERT_TRUE(s->waitForReads(kHangTimeout));
        }
    }
    const io::ImageryTileInfo* info = s->imagery().tileInfo(0, id);
    ASSERT_NE(info, nullptr);
    EXPECT_FALSE(info->present);
    EXPECT_EQ(s->imagery().ledger().submitted, 1U);
    EXPECT_EQ(*rules.reads, 1);
    EXPECT_EQ(s->imagery().pool().layersUsed(), 0);
    EXPECT_EQ(s->imagery().loadsOutstanding(), 0U);
}

TEST_F(ImageryStreamerTest, AnAbsentTileReadIntoARecycledBufferIsChargedItsInfoOnly) {
    FakeImageryRules rules;
    rules.absent = [](int, const io::PatchId& id) { return id.level == 2; };
    // Room for one present tile and a few absent ones.
    auto s = open(rules, 8, 0, 0.0,
                  cache::ImageryTileCache::kPresentTileBytes +
                      4 * cache::ImageryTileCache::kEntryOverheadBytes);
    ASSERT_TRUE(s);
    // a, then b: b's arrival evicts a from the CPU cache, whose buffer goes back to the I/O
    // thread, which reads the absent tile c into it.
    for (const io::PatchId& id :
         {io::PatchId{1, 0, 0}, io::PatchId{1, 1, 0}, io::PatchId{2, 0, 0}}) {
        for (int f = 0; f < 3; ++f) {
            frame(*s, [&](ImageryStreamer& imagery) { imagery.want(0, id, 1.0f); });
            if (s->imagery().requestsLive() > 0) {
                ASSERT_TRUE(s->waitForReads(kHangTimeout));
            }
        }
    }
    const io::ImageryTileInfo* absent = s->imagery().tileInfo(0, {2, 0, 0});
    ASSERT_NE(absent, nullptr);
    EXPECT_FALSE(absent->present);
    EXPECT_TRUE(s->imagery().cpuCache().contains({{1, 1, 0}, 0}))
        << "the absent tile was charged a whole tile's buffer";
    EXPECT_TRUE(s->imagery().pool().isResident({{1, 0, 0}, 0}));
    EXPECT_TRUE(s->imagery().pool().isResident({{1, 1, 0}, 0}));
}

TEST_F(ImageryStreamerTest, RequestsWantedByNoFrameForAFewFramesAreCancelled) {
    // Every read waits until it is cancelled: the requests stay live until the view moves on.
    auto s = open({}, 8, 0, 24.0 * 3600.0 * 1000.0);
    ASSERT_TRUE(s);
    const io::PatchId a{1, 0, 0};
    const io::PatchId b{1, 1, 0};
    frame(*s, [&](ImageryStreamer& imagery) {
        imagery.want(0, a, 2.0f);
        imagery.want(0, b, 1.0f);
    });
    EXPECT_EQ(s->imagery().requestsLive(), 2U);
    // b stays wanted; a is skipped for two frames (below cancelAfterFrames), then wanted.
    for (int f = 0; f < 2; ++f)
        frame(*s, [&](ImageryStreamer& imagery) { imagery.want(0, b, 1.0f); });
    frame(*s, [&](ImageryStreamer& imagery) {
        imagery.want(0, a, 2.0f);
        imagery.want(0, b, 1.0f);
    });
    EXPECT_EQ(m_sum.imageryRequestsCancelled, 0U);
    EXPECT_EQ(s->imagery().ledger().submitted, 2U) << "re-prioritised, not asked again";
    // Now neither is wanted: after cancelAfterFrames frames both are cancelled.
    for (int f = 0; f < 3; ++f) frame(*s, [](ImageryStreamer&) {});
    while (s->imagery().requestsLive() > 0) {
        frame(*s, [](ImageryStreamer&) {});
        if (s->imagery().requestsLive() > 0) {
            ASSERT_TRUE(s->waitForReads(kHangTimeout));
        }
    }
    EXPECT_EQ(m_sum.imageryRequestsCancelled, 2U);
    EXPECT_EQ(s->imagery().ledger().cancelled, 2U);
    EXPECT_EQ(s->imagery().loadsOutstanding(), 0U);
    EXPECT_EQ(s->imagery().pool().layersUsed(), 0);
    EXPECT_TRUE(s->drain(10s));
}

TEST_F(ImageryStreamerTest, AFailingTileIsReportedOnceAndNeverRetried) {
    FakeImageryRules rules;
    rules.fails = [](int layer, const io::PatchId& id) {
        return layer == 0 && id == io::PatchId{1, 1, 0};
    };
    auto s = open(rules, 8, /*failToOpen=*/0b10);
    ASSERT_TRUE(s);
    const io::PatchId id{1, 1, 0};
    for (int f = 0; f < 6; ++f) {
        frame(*s, [&](ImageryStreamer& imagery) {
            imagery.want(0, id, 1.0f);
            imagery.want(1, id, 1.0f);  // a layer that could not be opened
            // The draw keeps the ancestor: the root of layer 0 arrives and stays.
            imagery.want(0, {0, 0, 0}, 3.0f);
            imagery.gpuLayer(0, {0, 0, 0});
        });
        if (s->imagery().requestsLive() > 0) {
            ASSERT_TRUE(s->waitForReads(kHangTimeout));
        }
    }
    const std::vector<runtime::ImageryFault>& faults = s->imagery().faults();
    ASSERT_EQ(faults.size(), 2U);
    // The layer that could not be opened: one fault, from the start, for all its tiles.
    EXPECT_EQ(faults[0].layer, 1);
    EXPECT_NE(faults[0].message.find("\"layer1\": cannot be opened"), std::string::npos)
        << faults[0].message;
    EXPECT_EQ(faults[1].layer, 0);
    EXPECT_EQ(faults[1].id, id);
    EXPECT_NE(faults[1].message.find("cannot read tile L1 (1, 0)"), std::string::npos)
        << faults[1].message;
    EXPECT_TRUE(s->imagery().hasFailed(0, id));
    EXPECT_TRUE(s->imagery().hasFailed(1, id));
    EXPECT_TRUE(s->imagery().hasFailed(1, {0, 0, 0}));
    EXPECT_FALSE(s->imagery().hasFailed(0, {0, 0, 0}));
    EXPECT_EQ(s->imagery().ledger().submitted, 2U) << "the failing tile once, the root once";
    EXPECT_EQ(s->imagery().ledger().failed, 1U);
    EXPECT_EQ(*rules.reads, 2) << "layer 0's failing tile and root, read once each";
    EXPECT_EQ(m_sum.imageryRequestsFailed, 1U);
    EXPECT_TRUE(s->imagery().pool().isResident({{0, 0, 0}, 0}));
    FrameTelemetry t = frame(*s, [](ImageryStreamer&) {});
    EXPECT_EQ(t.imageryFaultsTotal, 2U);
    EXPECT_TRUE(s->faults().empty()) << "imagery faults are not the heights'";
}

TEST_F(ImageryStreamerTest, ATinyGpuBudgetEvictsOnlyTilesTheFrameDoesNotUse) {
    auto s = open({}, /*gpuTiles=*/3);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->imagery().pool().capacity(), 3);
    // Level 2 of the tiny pyramid as imagery: 8 × 4 tiles; a window of 3 slides over them.
    std::vector<io::PatchId> tiles;
    for (std::int64_t x = 0; x < 8; ++x) tiles.push_back({2, x, 1});
    int resident = 0;
    for (int f = 0; f < 60; ++f) {
        std::map<std::int64_t, int> used;  // x → layer drawn from this frame
        const std::size_t first = static_cast<std::size_t>(f / 6) % (tiles.size() - 2);
        frame(*s, [&](ImageryStreamer& imagery) {
            for (std::size_t i = first; i < first + 3; ++i) {
                imagery.want(0, tiles[i], 1.0f);
                if (const auto layer = imagery.gpuLayer(0, tiles[i])) used[tiles[i].x] = *layer;
            }
            // What the frame draws from is never taken by a later upload of the same frame.
            for (const auto& [x, layer] : used)
                EXPECT_EQ(imagery.pool().layerOf({{2, x, 1}, 0}), std::optional<int>(layer));
        });
        resident += static_cast<int>(used.size());
        if (s->imagery().requestsLive() > 0) {
            ASSERT_TRUE(s->waitForReads(kHangTimeout));
        }
    }
    EXPECT_GT(resident, 0);
    EXPECT_GT(m_sum.imageryGpuEvictions, 0U);
    EXPECT_LE(s->imagery().pool().layersUsed(), 3);
    EXPECT_TRUE(s->drain(10s));
    const runtime::ImageryRequestLedger& ledger = s->imagery().ledger();
    EXPECT_EQ(ledger.ended(), ledger.submitted);
    EXPECT_EQ(m_sum.imageryRequestsMade, ledger.submitted);
}

TEST_F(ImageryStreamerTest, WarmFramesAllocateNothingOnTheRenderThread) {
    // Six tiles in the CPU cache, three GPU layers: a window of two sliding over them
    // evicts and uploads every frame, from the CPU cache, with no read.
    auto s = open({}, /*gpuTiles=*/3, 0, 0.0, 8 * cache::ImageryTileCache::kPresentTileBytes);
    ASSERT_TRUE(s);
    std::vector<io::PatchId> tiles;
    for (std::int64_t x = 0; x < 6; ++x) tiles.push_back({2, x, 1});
    std::optional<int> sink;
    const auto body = [&](int f) {
        return [&, f](ImageryStreamer& imagery) {
            for (int i = 0; i < 2; ++i) {
                const io::PatchId& id = tiles[static_cast<std::size_t>((f + i) % 6)];
                imagery.want(0, id, 1.0f);
                sink = imagery.gpuLayer(0, id);
            }
        };
    };
    // Every tile read once: all wanted until all have arrived (one read a frame at least).
    for (int f = 0; f < 12 && s->imagery().cpuCache().entryCount() < 6; ++f) {
        frame(*s, [&](ImageryStreamer& imagery) {
            for (const io::PatchId& id : tiles) imagery.want(0, id, 1.0f);
        });
        if (s->imagery().requestsLive() > 0) {
            ASSERT_TRUE(s->waitForReads(kHangTimeout));
        }
    }
    ASSERT_EQ(s->imagery().cpuCache().entryCount(), 6U);
    for (int f = 0; f < 24; ++f) frame(*s, body(f));  // high-water marks

    const std::uint64_t uploadsBefore = s->imagery().ledger().submitted;
    FrameTelemetry t;
    std::uint64_t uploads = 0;
    const AllocationScope scope;
    for (int f = 0; f < 24; ++f) {
        s->beginFrame();
        body(f)(s->imagery());
        s->endFrame(t);
        uploads += t.imageryGpuUploads;
    }
    EXPECT_EQ(scope.allocations(), 0U);
    EXPECT_GT(uploads, 0U) << "the frames measured did evict and upload";
    EXPECT_EQ(s->imagery().ledger().submitted, uploadsBefore) << "no read: all from the cache";
    EXPECT_EQ(s->checkInvariants(), std::nullopt);
}

}  // namespace
}  // namespace terrain::test
