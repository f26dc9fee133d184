// runtime::LodQuadtree on a real context and the streaming test pyramid: it settles on the
// same cut as selecting from the root, keeps its invariants (leaves tile the domain, only
// complete child sets, every node pinned and resident) through a flight, a static camera
// changes nothing (no flicker, no work), small moves near thresholds do not pop, and a
// changed ε re-evaluates everything.
#include "GlTestFixture.h"
#include "StreamingTestPyramid.h"
#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TileStreamer.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

namespace terrain::test {
namespace {

using runtime::Camera;
using runtime::LodQuadtree;
using runtime::LodUpdateStats;
using runtime::PatchDraw;
using runtime::TileStreamer;

class LodQuadtreeTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        auto opened = TileStreamer::open(streamingTestPyramid(), {});
        ASSERT_TRUE(opened) << opened.error().message;
        m_streamer = std::move(opened).value();
        m_geometry.emplace(m_streamer->manifest());
    }
    void TearDown() override {
        m_tree.reset();
        m_streamer.reset();
        GlTest::TearDown();
    }

    Camera camera(double fx, double fy, double above, double tx, double ty) const {
        Camera c;
        c.viewportWidth = 640;
        c.viewportHeight = 480;
        c.fovY = 1.0;
        c.position = {m_geometry->worldAtFraction(fx, fy), m_geometry->maxHeight() + above};
        c.lookAt({m_geometry->worldAtFraction(tx, ty), m_geometry->minHeight()});
        return c;
    }

    LodUpdateStats frame(const Camera& c) {
        m_streamer->beginFrame();
        const LodUpdateStats stats = m_tree->update(c, m_draws);
        runtime::FrameTelemetry t;
        m_streamer->endFrame(t);
        return stats;
    }

    /// Frames until no split is waiting for children and nothing is loading.
    LodUpdateStats settle(const Camera& c) {
        LodUpdateStats stats;
        for (int i = 0; i < 3000; ++i) {
            stats = frame(c);
            if (i > 1 && stats.waitingSplits == 0 && m_streamer->loadsOutstanding() == 0 &&
                stats.splits == 0 && stats.merges == 0) {
                return stats;
            }
            std::this_thread::sleep_for(std::chrono::microseconds(300));
        }
        ADD_FAILURE() << "the tree never settled";
        return stats;
    }

    static std::vector<io::PatchId> ids(const std::vector<PatchDraw>& draws) {
        std::vector<io::PatchId> out;
        for (const PatchDraw& d : draws) out.push_back(d.id);
        std::sort(out.begin(), out.end(), [](const io::PatchId& a, const io::PatchId& b) {
            return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
        });
        return out;
    }

    std::unique_ptr<TileStreamer> m_streamer;
    std::optional<runtime::TerrainGeometry> m_geometry;
    std::unique_ptr<LodQuadtree> m_tree;
    std::vector<PatchDraw> m_draws;
};

TEST_F(LodQuadtreeTest, SettlesOnTheCutOfASelectionFromTheRoot) {
    const runtime::LodOptions options{.errorPx = 1.0};
    m_tree = std::make_unique<LodQuadtree>(*m_streamer, *m_geometry, options);
    const Camera c = camera(0.2, 0.3, 300.0, 0.6, 0.5);
    const LodUpdateStats settled = settle(c);
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
    EXPECT_GT(settled.drawn, 8u);
    EXPECT_EQ(settled.coveredFinestPatches,
              runtime::finestPatchesCovered(m_streamer->layout(), {0, 0, 0}));
    const std::vector<io::PatchId> fromTree = ids(m_draws);

    std::vector<PatchDraw> fromRoot;
    m_streamer->beginFrame();
    const runtime::PatchSelectionStats reference =
        runtime::selectPatches(c, *m_geometry, options.coarseErrorPx(), *m_streamer, fromRoot);
    runtime::FrameTelemetry t;
    m_streamer->endFrame(t);
    EXPECT_EQ(reference.waitingSplits, 0u);
    EXPECT_EQ(fromTree, ids(fromRoot));
}

TEST_F(LodQuadtreeTest, StaticCameraChangesNothingAndCostsNothing) {
    m_tree = std::make_unique<LodQuadtree>(*m_streamer, *m_geometry);
    const Camera c = camera(0.5, 0.5, 150.0, 0.5, 0.9);
    settle(c);
    const std::vector<io::PatchId> before = ids(m_draws);
    for (int i = 0; i < 20; ++i) {
        const LodUpdateStats s = frame(c);
        EXPECT_EQ(s.evaluations, 0u) << "frame " << i;
        EXPECT_EQ(s.splits + s.merges, 0u);
        EXPECT_EQ(ids(m_draws), before);
    }
    // Moving back and forth by a metre near the thresholds does not pop.
    std::uint64_t changes = 0;
    for (int i = 0; i < 40; ++i) {
        Camera moved = c;
        moved.position.x += (i % 2 == 0) ? 1.0 : -1.0;
        const LodUpdateStats s = frame(moved);
        changes += s.splits + s.merges;
    }
    EXPECT_EQ(changes, 0u) << "hysteresis keeps small moves from splitting and merging";
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
}

TEST_F(LodQuadtreeTest, InvariantsHoldThroughAFlightAndTreeFollowsTheCamera) {
    m_tree = std::make_unique<LodQuadtree>(*m_streamer, *m_geometry);
    std::uint64_t splits = 0, merges = 0, framesDrawn = 0;
    int maxLevelNear = 0;
    for (int i = 0; i < 400; ++i) {
        const double t = i / 400.0;
        const Camera c = camera(0.1 + 0.8 * t, 0.1 + 0.8 * t, 50.0 + 3000.0 * t * t, 0.9, 0.9);
        const LodUpdateStats s = frame(c);
        splits += s.splits;
        merges += s.merges;
        if (s.drawn > 0) {
            ++framesDrawn;
            ASSERT_EQ(s.coveredFinestPatches,
                      runtime::finestPatchesCovered(m_streamer->layout(), {0, 0, 0}))
                << "frame " << i;
        }
        if (i % 25 == 0) {
            ASSERT_EQ(m_tree->checkInvariants(), std::nullopt) << "frame " << i;
        }
        for (const PatchDraw& d : m_draws) {
            ASSERT_TRUE(m_streamer->pool().isResident(d.id));
            if (i < 100) maxLevelNear = std::max(maxLevelNear, d.id.level);
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    EXPECT_GT(framesDrawn, 350u);
    EXPECT_GT(splits, 0u);
    EXPECT_GT(merges, 0u) << "climbing away merges what was split near the ground";
    EXPECT_EQ(maxLevelNear, m_streamer->layout().finestLevel());
}

TEST_F(LodQuadtreeTest, ChangingTheThresholdReevaluatesEverything) {
    m_tree = std::make_unique<LodQuadtree>(*m_streamer, *m_geometry,
                                           runtime::LodOptions{.errorPx = 4.0});
    const Camera c = camera(0.3, 0.3, 200.0, 0.7, 0.7);
    const LodUpdateStats coarse = settle(c);
    m_tree->setOptions({.errorPx = 0.5});
    const LodUpdateStats fine = settle(c);
    EXPECT_GT(fine.drawn, coarse.drawn);
    m_tree->setOptions({.errorPx = 4.0});
    const LodUpdateStats back = settle(c);
    // Back to the coarse cut, except where hysteresis keeps a split whose parent's error
    // lies between ε / hysteresis and ε.
    EXPECT_LT(back.drawn, fine.drawn);
    EXPECT_GE(back.drawn, coarse.drawn);
    EXPECT_LE(back.drawn, coarse.drawn + coarse.drawn / 4);
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
}

}  // namespace
}  // namespace terrain::test

namespace terrain::test {
namespace {

// Leaves that can never split — the finest level with the camera inside its box, or a
// patch whose child failed to load — once re-scheduled their own check at zero travel and
// a frame never ended. Every frame must end, and a still camera must cost nothing.
TEST_F(LodQuadtreeTest, UnsplittableLeavesDoNotRecheckWithinAFrame) {
    runtime::TileStreamerOptions options;
    options.io.faults = {.errorRate = 0.3, .addedLatencyMs = 0.0, .seed = 3};
    auto opened = TileStreamer::open(streamingTestPyramid(), options);
    ASSERT_TRUE(opened) << opened.error().message;
    m_streamer = std::move(opened).value();
    m_tree = std::make_unique<LodQuadtree>(*m_streamer, *m_geometry,
                                           runtime::LodOptions{.errorPx = 0.5});
    // Just above the highest sample: inside the bounding boxes of the patches below.
    Camera c = camera(0.5, 0.5, 0.5, 0.55, 0.55);
    c.position.z = m_geometry->maxHeight() - 1.0;
    settle(c);
    EXPECT_GT(m_streamer->faults().size(), 0u);
    for (int i = 0; i < 10; ++i) {
        const LodUpdateStats s = frame(c);
        EXPECT_EQ(s.evaluations, 0u) << "frame " << i;
    }
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
}

}  // namespace
}  // namespace terrain::test
