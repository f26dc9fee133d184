// runtime::selectPatches on FakeTileResidency (one thread, no GL, no sleeps): nothing is
// drawn before the root arrives, the selection settles on a resident cover of the view that
// reaches the finest level where a low view needs it, a settled static view asks for
// nothing, and with tiny budgets, late tiles and failed loads every frame's drawn and
// culled patches still tile the domain exactly once, none overlapping another: no hole.
#include "FakeTileResidency.h"
#include "StreamingTestPyramid.h"
#include "TestCameras.h"
#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <random>
#include <unordered_set>
#include <vector>

namespace terrain::test {
namespace {

using runtime::Camera;
using runtime::PatchDraw;
using runtime::PatchSelectionStats;

class PatchSelectionTest : public ::testing::Test {
protected:
    void open(const FakeTileResidencyOptions& options) {
        m_residency = FakeTileResidency::fromPyramid(streamingTestPyramid(), options);
        ASSERT_TRUE(m_residency);
        m_geometry.emplace(streamingTestManifest());
    }

    Camera lowOblique() const { return cameraOverDem(*m_geometry, 0.3, 0.2, 200.0, 0.6, 0.7); }

    PatchSelectionStats frame(const Camera& c, double errorPx) {
        m_residency->beginFrame();
        const PatchSelectionStats stats =
            runtime::selectPatches(c, *m_geometry, errorPx, *m_residency, m_draws);
        m_residency->endFrame();
        return stats;
    }

    /// Drawn patches are resident on their layers, never failed, and with the culled ones
    /// cover every finest-level patch exactly once; no drawn patch overlaps another.
    void expectCover(const PatchSelectionStats& stats) const {
        EXPECT_EQ(stats.coveredFinestPatches,
                  runtime::finestPatchesCovered(m_residency->layout(), {0, 0, 0}));
        std::unordered_set<io::PatchId, io::PatchIdHash> drawn;
        for (const PatchDraw& d : m_draws) {
            EXPECT_NE(m_residency->residentInfo(d.id), nullptr);
            EXPECT_EQ(m_residency->layerOf(d.id), d.layer);
            EXPECT_FALSE(m_residency->hasFailed(d.id));
            EXPECT_TRUE(drawn.insert(d.id).second) << "drawn twice";
        }
        for (const PatchDraw& d : m_draws) {
            for (io::PatchId up = d.id; up.level > 0;) {
                up = {up.level - 1, up.x / 2, up.y / 2};
                EXPECT_FALSE(drawn.contains(up)) << "a drawn patch overlaps an ancestor";
            }
        }
    }

    std::unique_ptr<FakeTileResidency> m_residency;
    std::optional<runtime::TerrainGeometry> m_geometry;
    std::vector<PatchDraw> m_draws;
};

TEST_F(PatchSelectionTest, SettlesOnAResidentCoverOfTheView) {
    open({.framesToArrive = 1});
    const Camera c = lowOblique();
    PatchSelectionStats stats = frame(c, 1.0);
    EXPECT_TRUE(m_draws.empty()) << "nothing can draw before the root arrives";
    EXPECT_EQ(stats.visited, 0u);
    const int levels = m_residency->layout().levelCount();
    // One level a frame: the root on frame 2, the finest level by frame levels + 1.
    for (int i = 0; i < levels + 1; ++i) stats = frame(c, 1.0);
    EXPECT_EQ(stats.waitingSplits, 0u);
    EXPECT_EQ(m_residency->pending(), 0u);
    expectCover(stats);
    EXPECT_GT(m_draws.size(), 4u);
    EXPECT_GT(stats.culled, 0u) << "the oblique view sees only part of the DEM";
    int finest = 0;
    for (const PatchDraw& d : m_draws) finest = std::max(finest, d.id.level);
    EXPECT_EQ(finest, levels - 1) << "a low view at 1 px needs the finest level somewhere";

    // A static camera changes nothing once settled and asks for nothing.
    const std::vector<PatchDraw> before = m_draws;
    const std::uint64_t requests = m_residency->requests();
    stats = frame(c, 1.0);
    EXPECT_EQ(m_residency->requests(), requests);
    ASSERT_EQ(m_draws.size(), before.size());
    for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(m_draws[i].id, before[i].id);
}

TEST_F(PatchSelectionTest, TinyBudgetsLateTilesAndFailuresNeverLeaveAHole) {
    open({.capacity = 12,
          .framesToArrive = 2,
          .arrivalsPerFrame = 1,
          .fails = [](const io::PatchId& id) {
              return id.level > 1 && (id.x * 5 + id.y * 11 + id.level) % 5 == 1;
          }});
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Camera c = lowOblique();
    std::uint64_t framesDrawn = 0, framesWaiting = 0, maxDrawn = 0;
    for (int i = 0; i < 600; ++i) {
        if (i % 20 == 0) {  // teleport
            const double fx = u(random), fy = u(random);
            c.position = {m_geometry->worldAtFraction(fx, fy),
                          m_geometry->maxHeight() + 10.0 + 2000.0 * u(random)};
            const double tx = u(random), ty = u(random);
            c.lookAt({m_geometry->worldAtFraction(tx, ty), m_geometry->minHeight()});
        }
        const PatchSelectionStats stats = frame(c, 0.5);
        if (i < 2) {
            EXPECT_EQ(stats.visited, 0u) << "the root arrives on frame 3";
            continue;
        }
        ++framesDrawn;
        framesWaiting += stats.waitingSplits > 0 ? 1 : 0;
        maxDrawn = std::max<std::uint64_t>(maxDrawn, stats.drawn);
        ASSERT_NO_FATAL_FAILURE(expectCover(stats)) << "frame " << i;
    }
    EXPECT_EQ(framesDrawn, 598u);
    EXPECT_GT(framesWaiting, framesDrawn / 2) << "one tile a frame keeps splits waiting";
    EXPECT_GT(m_residency->failed().size(), 0u);
    EXPECT_GT(m_residency->evictions(), 0u) << "12 layers cannot hold the views";
    EXPECT_GT(maxDrawn, 4u) << "the views refine beyond the root's children";
}

// A whole area whose loads fail (a lost shard's patches) is drawn by resident ancestors.
TEST_F(PatchSelectionTest, AFailedAreaIsDrawnByItsAncestors) {
    const int finest = streamingTestManifest().layout.finestLevel();
    // The finest patches of the north-west shard (4 × 4 patches).
    const auto lost = [finest](const io::PatchId& id) {
        return id.level == finest && id.x < 4 && id.y < 4;
    };
    open({.fails = lost});
    // Low over the north-west corner, looking down.
    const Camera c = cameraOverDem(*m_geometry, 0.05, 0.05, 50.0, 0.1, 0.1);
    PatchSelectionStats stats;
    for (int i = 0; i < 20; ++i) stats = frame(c, 0.5);
    EXPECT_EQ(m_residency->pending(), 0u);
    ASSERT_FALSE(m_residency->failed().empty()) << "the view needs patches of the lost area";
    for (const io::PatchId& id : m_residency->failed()) EXPECT_TRUE(lost(id));
    expectCover(stats);
    for (const PatchDraw& d : m_draws) EXPECT_FALSE(lost(d.id)) << "a lost patch is drawn";
    EXPECT_GT(m_draws.size(), 0u);
}

}  // namespace
}  // namespace terrain::test
