// runtime::LodQuadtree on FakeTileResidency (one thread, no GL, no sleeps: tiles arrive on
// the frame the fake says): it settles on the same cut as selecting from the root, keeps its
// invariants (leaves tile the domain, only complete child sets, every node pinned and
// resident) through a flight with late, budgeted and failing tiles, a static camera changes
// nothing (no flicker, no work), small moves near thresholds do not pop, a changed ε
// re-evaluates everything, and the tree gives back every pin it took.
#include "FakeTileResidency.h"
#include "StreamingTestPyramid.h"
#include "TestCameras.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/LodQuadtree.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace terrain::test {
namespace {

using runtime::Camera;
using runtime::LodQuadtree;
using runtime::LodUpdateStats;
using runtime::PatchDraw;

class LodQuadtreeTest : public ::testing::Test {
protected:
    void SetUp() override { open({}); }
    void TearDown() override { m_tree.reset(); }

    void open(const FakeTileResidencyOptions& options) {
        m_tree.reset();
        m_residency = FakeTileResidency::fromPyramid(streamingTestPyramid(), options);
        ASSERT_TRUE(m_residency);
        m_surface = std::make_unique<runtime::PlaneSurface>(streamingTestManifest());
        m_geometry.emplace(streamingTestManifest());
    }

    Camera camera(double fx, double fy, double above, double tx, double ty) const {
        return cameraOverDem(*m_geometry, fx, fy, above, tx, ty);
    }

    LodUpdateStats frame(const Camera& c) {
        m_residency->beginFrame();
        const LodUpdateStats stats = m_tree->update(c, m_draws);
        m_residency->endFrame();
        return stats;
    }

    /// Frames until no split is waiting for children and nothing is loading: with tiles
    /// that arrive a frame after they are asked for, a handful per level.
    LodUpdateStats settle(const Camera& c) {
        LodUpdateStats stats;
        for (int i = 0; i < 100; ++i) {
            stats = frame(c);
            if (stats.drawn > 0 && stats.waitingSplits == 0 && m_residency->pending() == 0 &&
                stats.splits == 0 && stats.merges == 0) {
                return stats;
            }
        }
        ADD_FAILURE() << "the tree did not settle in 100 frames: " << stats.splits << " splits, "
                      << stats.merges << " merges, " << stats.waitingSplits << " waiting, "
                      << m_residency->pending() << " pending, " << stats.drawn << " drawn";
        return stats;
    }

    std::uint64_t domain() const {
        return runtime::finestPatchesCovered(m_residency->layout(), {0, 0, 0});
    }

    static std::vector<io::PatchId> ids(const std::vector<PatchDraw>& draws) {
        std::vector<io::PatchId> out;
        for (const PatchDraw& d : draws) out.push_back(d.id);
        std::sort(out.begin(), out.end(), [](const io::PatchId& a, const io::PatchId& b) {
            return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
        });
        return out;
    }

    /// The tree under a split rule of the level's spacing settles on the cut of the
    /// rule's traversal from the root, for three views.
    void checkSpacingRuleCut(runtime::SplitRule rule);

    std::unique_ptr<FakeTileResidency> m_residency;
    std::unique_ptr<runtime::PlaneSurface> m_surface;
    std::optional<runtime::TerrainGeometry> m_geometry;
    std::unique_ptr<LodQuadtree> m_tree;
    std::vector<PatchDraw> m_draws;
};

TEST_F(LodQuadtreeTest, DrawsTheRootOnTheFrameItArrives) {
    open({.framesToArrive = 3});
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface);
    const Camera c = camera(0.5, 0.5, 2000.0, 0.5, 0.6);
    for (int i = 1; i <= 3; ++i) {
        EXPECT_EQ(frame(c).drawn, 0u) << "frame " << i << ": the root is not resident yet";
        EXPECT_TRUE(m_draws.empty());
    }
    const LodUpdateStats fourth = frame(c);
    ASSERT_EQ(m_draws.size(), 1u) << "the root arrives on frame 4 and is drawn at once";
    EXPECT_EQ(m_draws[0].id, (io::PatchId{0, 0, 0}));
    EXPECT_EQ(m_draws[0].layer, m_residency->layerOf({0, 0, 0}));
    EXPECT_EQ(fourth.coverage, domain());
    EXPECT_TRUE(m_residency->isPinned({0, 0, 0}));
}

TEST_F(LodQuadtreeTest, SettlesOnTheCutOfASelectionFromTheRoot) {
    const runtime::LodOptions options{.errorPx = 1.0};
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface, options);
    const Camera c = camera(0.2, 0.3, 300.0, 0.6, 0.5);
    const LodUpdateStats settled = settle(c);
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
    EXPECT_GT(settled.drawn, 8u);
    EXPECT_EQ(settled.coverage, domain());

    std::vector<PatchDraw> fromRoot;
    m_residency->beginFrame();
    const runtime::PatchSelectionStats reference = runtime::selectPatches(
        c, *m_geometry, options.coarseErrorPx(runtime::SurfaceKind::Plane), *m_residency, fromRoot);
    m_residency->endFrame();
    EXPECT_EQ(reference.waitingSplits, 0u);
    EXPECT_EQ(ids(m_draws), ids(fromRoot));
}

TEST_F(LodQuadtreeTest, PrefetchReachesTheSameCutInFewerFrames) {
    // A teleport: nothing resident, the camera low over the terrain. Tiles arrive a frame
    // after they are asked for, so without prefetching the tree refines a level a frame;
    // reading ahead the levels it predicts below the children it waits for, it reaches the
    // same cut sooner (issue 49). A prediction never changes a decision: the same patches.
    const runtime::LodOptions options{.errorPx = 1.0};
    const Camera c = camera(0.2, 0.3, 60.0, 0.6, 0.5);
    auto framesToSettle = [&](bool prefetch, std::vector<io::PatchId>& cut,
                              std::uint64_t& prefetchCalls) {
        open({.framesToArrive = 1, .honourPrefetch = prefetch});
        m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface, options);
        for (int frames = 1; frames <= 100; ++frames) {
            const LodUpdateStats stats = frame(c);
            if (stats.drawn > 0 && stats.waitingSplits == 0 && m_residency->pending() == 0 &&
                stats.splits == 0 && stats.merges == 0) {
                cut = ids(m_draws);
                prefetchCalls = m_residency->prefetchCalls();
                EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
                return frames;
            }
        }
        ADD_FAILURE() << "did not settle";
        return 0;
    };
    std::vector<io::PatchId> levelByLevel, ahead;
    std::uint64_t callsWithout = 0, callsWith = 0;
    const int without = framesToSettle(false, levelByLevel, callsWithout);
    const int with = framesToSettle(true, ahead, callsWith);
    EXPECT_GT(callsWith, 0u);
    EXPECT_LT(with, without);
    EXPECT_EQ(ahead, levelByLevel);
    EXPECT_GE(levelByLevel.back().level, 3) << "deep enough to need prefetching";
}

TEST_F(LodQuadtreeTest, ReadingAheadAlongTheCameraMotionSavesWaitsOnTheWay) {
    // A descent from high above to low over the terrain, 48 frames, tiles arriving 3 frames
    // after they are asked for. Reading ahead, the children of the leaves the camera heads
    // for are asked for before their parents want to split (prefetchAlongMotion), so far
    // fewer splits wait on the way than with no reading ahead, or with the reading ahead
    // below waiting leaves alone (readAheadFrames 0); the cut once the camera rests is the same.
    constexpr int kFrames = 48;
    auto fly = [&](bool prefetch, double readAheadFrames, std::uint64_t& waits,
                   std::uint64_t& aheadWithoutWait, std::vector<io::PatchId>& cut) {
        open({.capacity = 2048, .framesToArrive = 3, .honourPrefetch = prefetch});
        const runtime::LodOptions options{.errorPx = 1.0, .readAheadFrames = readAheadFrames};
        m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface, options);
        settle(camera(0.1, 0.1, 3000.0, 0.5, 0.5));
        waits = aheadWithoutWait = 0;
        for (int f = 1; f <= kFrames; ++f) {
            const double t = double(f) / kFrames;
            const LodUpdateStats stats =
                frame(camera(0.1 + 0.3 * t, 0.1 + 0.2 * t, 3000.0 * std::pow(60.0 / 3000.0, t),
                             0.5 + 0.1 * t, 0.5));
            waits += stats.waitingSplits;
            if (stats.waitingSplits == 0 && stats.prefetched > 0) ++aheadWithoutWait;
        }
        settle(camera(0.4, 0.3, 60.0, 0.6, 0.5));
        EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
        cut = ids(m_draws);
    };
    const double aheadFrames = runtime::LodOptions{}.readAheadFrames;
    std::uint64_t waitsWithout = 0, waitsBelow = 0, waitsWith = 0;
    std::uint64_t aheadWithout = 0, aheadBelow = 0, ahead = 0;
    std::vector<io::PatchId> cutWithout, cutBelow, cutWith;
    fly(false, aheadFrames, waitsWithout, aheadWithout, cutWithout);
    fly(true, 0.0, waitsBelow, aheadBelow, cutBelow);
    fly(true, aheadFrames, waitsWith, ahead, cutWith);
    EXPECT_GT(ahead, 0u) << "reads ahead on frames where no split waits: the motion's";
    EXPECT_EQ(aheadBelow, 0u) << "below waiting leaves only: nothing ahead without a wait";
    EXPECT_LT(2 * waitsWith, waitsWithout)
        << waitsWith << " waits reading ahead, " << waitsWithout << " without";
    EXPECT_LT(2 * waitsWith, waitsBelow)
        << waitsWith << " waits reading ahead, " << waitsBelow << " below waiting leaves only";
    EXPECT_EQ(cutWith, cutWithout);
    EXPECT_EQ(cutBelow, cutWithout);
    RecordProperty("waits", std::to_string(waitsWith) + " reading ahead, " +
                                std::to_string(waitsBelow) + " below waiting leaves only, " +
                                std::to_string(waitsWithout) + " without");
}

TEST_F(LodQuadtreeTest, SplitToFinestDrawsTheUniformGridOfWhatIsInView) {
    // The uniform grid (LodMethod::Uniform): every leaf in view at the finest level, from
    // high above (where the error rule would draw the root alone) and after moving away.
    // It holds every finest patch in view and their ancestors (the tree pins them): room
    // for the whole DEM.
    open({.capacity = 512});
    const runtime::LodOptions options{.errorPx = 1000.0, .splitToFinest = true};
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface, options);
    const int finest = m_residency->layout().finestLevel();
    for (const Camera& c :
         {camera(0.5, 0.5, 50000.0, 0.5, 0.6), camera(0.1, 0.1, 200.0, 0.9, 0.9)}) {
        const LodUpdateStats settled = settle(c);
        EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
        EXPECT_EQ(settled.coverage, domain());
        ASSERT_FALSE(m_draws.empty());
        for (const PatchDraw& d : m_draws)
            EXPECT_EQ(d.id.level, finest) << "patch " << d.id.x << "," << d.id.y;
        // Nothing merges back while the camera rests.
        const LodUpdateStats again = frame(c);
        EXPECT_EQ(again.merges, 0u);
        EXPECT_EQ(again.splits, 0u);
    }
}

TEST_F(LodQuadtreeTest, SpacingRulesSettleOnTheCutsOfTheirTopDownTraversals) {
    // Livny 2007's rule (SplitRule::LivnyEdges) and CDLOD's ranges (ProjectedSpacing) in the
    // persistent tree give what the papers' traversals from the root give (Livny §3,
    // "Runtime Rendering"): a visible patch is split while γ · s / d > τ, s its level's
    // spacing, d the distance to its nearest edge (livnyEdgeDistance) or to its box.
    for (const runtime::SplitRule rule :
         {runtime::SplitRule::LivnyEdges, runtime::SplitRule::ProjectedSpacing}) {
        checkSpacingRuleCut(rule);
    }
}

void LodQuadtreeTest::checkSpacingRuleCut(runtime::SplitRule rule) {
    SCOPED_TRACE(rule == runtime::SplitRule::LivnyEdges ? "LivnyEdges" : "ProjectedSpacing");
    const runtime::LodOptions options{
        .errorPx = 12.0, .coarseShare = 1.0, .hysteresis = 1.0, .splitRule = rule};
    auto reader = io::PyramidReader::open(streamingTestPyramid());
    ASSERT_TRUE(reader) << reader.error().message;
    const io::PyramidLayout& layout = reader.value().layout();
    for (const Camera& c : {camera(0.2, 0.3, 300.0, 0.6, 0.5), camera(0.5, 0.5, 40.0, 0.9, 0.1),
                            camera(0.9, 0.1, 1500.0, 0.2, 0.8)}) {
        // A tree of its own for each view (the fake keeps requests the last view left).
        open({.capacity = 1024});
        m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface, options);
        settle(c);
        EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
        std::vector<PatchDraw> expected;
        const runtime::Frustum frustum = c.frustum();
        const auto visit = [&](const auto& self, const io::PatchId& id) -> void {
            auto info = reader.value().patchInfo(id);
            ASSERT_TRUE(info) << info.error().message;
            const runtime::Aabb box = m_geometry->patchBounds(id, info.value());
            if (!frustum.intersects(box)) return;
            const glm::dvec2 spacing =
                m_geometry->sampleSpacing() * static_cast<double>(layout.levelStep(id.level));
            const double d =
                rule == runtime::SplitRule::LivnyEdges
                    ? runtime::livnyEdgeDistance(c.position, box, m_geometry->minHeight(),
                                                 m_geometry->maxHeight())
                    : runtime::distanceToBox(c.position, box);
            const double epsilon =
                d > 0.0 ? c.errorScale() * std::max(spacing.x, spacing.y) / d : 1e300;
            if (id.level < layout.finestLevel() && epsilon > options.errorPx) {
                io::PatchId children[4];
                const int count = runtime::containedChildren(layout, id, children);
                for (int i = 0; i < count; ++i) self(self, children[i]);
                return;
            }
            expected.push_back({.id = id});
        };
        visit(visit, io::PatchId{0, 0, 0});
        EXPECT_EQ(ids(m_draws), ids(expected));
        std::set<int> levels;
        for (const PatchDraw& d : m_draws) levels.insert(d.id.level);
        EXPECT_GT(levels.size(), 1u) << "the view should mix levels";
    }
}

TEST_F(LodQuadtreeTest, StaticCameraChangesNothingAndCostsNothing) {
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface);
    const Camera c = camera(0.5, 0.5, 150.0, 0.5, 0.9);
    settle(c);
    const std::vector<io::PatchId> before = ids(m_draws);
    const std::uint64_t requests = m_residency->requests();
    for (int i = 0; i < 20; ++i) {
        const LodUpdateStats s = frame(c);
        EXPECT_EQ(s.evaluations, 0u) << "frame " << i;
        EXPECT_EQ(s.splits + s.merges, 0u);
        EXPECT_EQ(ids(m_draws), before);
    }
    EXPECT_EQ(m_residency->requests(), requests) << "a settled view asks for nothing";
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
    open({.framesToArrive = 2, .arrivalsPerFrame = 4});
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface);
    std::uint64_t splits = 0, merges = 0, framesDrawn = 0;
    int maxLevelNear = 0;
    for (int i = 0; i < 400; ++i) {
        const double t = i / 400.0;
        const Camera c = camera(0.1 + 0.8 * t, 0.1 + 0.8 * t, 50.0 + 3000.0 * t * t, 0.9, 0.9);
        const LodUpdateStats s = frame(c);
        splits += s.splits;
        merges += s.merges;
        if (i >= 2) {
            ASSERT_GT(s.drawn, 0u) << "frame " << i << ": the root arrived on frame 3";
            ++framesDrawn;
            ASSERT_EQ(s.coverage, domain()) << "frame " << i;
        }
        ASSERT_EQ(m_tree->checkInvariants(), std::nullopt) << "frame " << i;
        for (const PatchDraw& d : m_draws) {
            ASSERT_NE(m_residency->residentInfo(d.id), nullptr);
            ASSERT_EQ(m_residency->layerOf(d.id), d.layer);
            if (i < 100) maxLevelNear = std::max(maxLevelNear, d.id.level);
        }
    }
    EXPECT_EQ(framesDrawn, 398u);
    EXPECT_GT(splits, 0u);
    EXPECT_GT(merges, 0u) << "climbing away merges what was split near the ground";
    EXPECT_EQ(maxLevelNear, m_residency->layout().finestLevel());
}

TEST_F(LodQuadtreeTest, ChangingTheThresholdReevaluatesEverything) {
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface,
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

// LodOptions::maxSamplePx: at an ε so large that the geometric rule alone draws a coarse cut,
// the sample rule refines it (only refines: every patch at least as deep as in the geometric
// cut) until a sample spans at most a pixel where the finer data shades differently, and
// the tree keeps its invariants.
TEST_F(LodQuadtreeTest, SamplesSpanAtMostAPixelWhereFinerDataShadesDifferently) {
    const Camera c = camera(0.3, 0.3, 400.0, 0.7, 0.7);
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface,
                                           runtime::LodOptions{.errorPx = 50.0});
    settle(c);
    const std::vector<PatchDraw> geometric = m_draws;
    m_tree = std::make_unique<LodQuadtree>(
        *m_residency, *m_surface, runtime::LodOptions{.errorPx = 50.0, .maxSamplePx = 1.0});
    settle(c);
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
    EXPECT_GT(m_draws.size(), 2 * geometric.size());
    const auto levelAt = [](const std::vector<PatchDraw>& cut, const io::PatchId& id) {
        for (const PatchDraw& d : cut) {
            const int up = id.level - d.id.level;
            if (up >= 0 && (id.x >> up) == d.id.x && (id.y >> up) == d.id.y) return d.id.level;
        }
        return -1;  // culled in that cut
    };
    for (const PatchDraw& d : m_draws) {
        const int before = levelAt(geometric, d.id);
        if (before >= 0) {
            EXPECT_GE(d.id.level, before) << "patch " << d.id.x << "," << d.id.y;
        }
    }
    // Back to the geometric rule: the coarse cut again (merging where it may).
    m_tree->setOptions({.errorPx = 50.0});
    settle(c);
    EXPECT_LE(m_draws.size(), geometric.size() + geometric.size() / 4);
}

// Never a hole while streaming: teleports far faster than tiles arrive (3 frames late, 2 a
// frame), a pool of 40 layers for 341 patches and one load in ten failing. Every frame the
// drawn and culled leaves tile the domain exactly once, every drawn patch is resident on its
// layer and none failed; the views refine beyond the root and splits do wait for tiles.
TEST_F(LodQuadtreeTest, NeverAHoleWithLateBudgetedAndFailingTiles) {
    open({.capacity = 40,
          .framesToArrive = 3,
          .arrivalsPerFrame = 2,
          .fails = [](const io::PatchId& id) {
              return id.level > 0 && (id.x * 7 + id.y * 13 + id.level) % 10 == 3;
          }});
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface,
                                           runtime::LodOptions{.errorPx = 1.0});
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::uniform_int_distribution<int> holdFrames(1, 10);
    int frames = 0, framesWaiting = 0, teleports = 0;
    std::uint64_t maxDrawn = 0;
    while (frames < 300) {
        const Camera c =
            camera(u(random), u(random), 10.0 + 2000.0 * u(random), u(random), u(random));
        ++teleports;
        for (int hold = holdFrames(random); hold > 0 && frames < 300; --hold, ++frames) {
            const LodUpdateStats s = frame(c);
            ASSERT_EQ(m_tree->checkInvariants(), std::nullopt) << "frame " << frames;
            if (frames < 3) continue;  // the root arrives on frame 4
            ASSERT_EQ(s.coverage, domain()) << "frame " << frames;
            for (const PatchDraw& d : m_draws) {
                ASSERT_EQ(m_residency->layerOf(d.id), d.layer);
                ASSERT_FALSE(m_residency->hasFailed(d.id));
            }
            framesWaiting += s.waitingSplits > 0 ? 1 : 0;
            maxDrawn = std::max(maxDrawn, s.drawn);
        }
    }
    EXPECT_GT(framesWaiting, frames / 3) << "tiles were late for many frames";
    EXPECT_GT(m_residency->failed().size(), 0u);
    EXPECT_GT(m_residency->evictions(), 0u) << "40 layers cannot hold every view";
    EXPECT_GT(maxDrawn, 4u) << "the views refine beyond the root";
    EXPECT_LE(m_residency->pinnedCount(), 40u);
}

// A patch whose child failed keeps drawing in its place and never splits again; its
// siblings' subtrees are unaffected.
TEST_F(LodQuadtreeTest, AFailedChildKeepsItsParentDrawing) {
    const io::PatchId lost{2, 1, 1};
    open({.fails = [lost](const io::PatchId& id) { return id == lost; }});
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface,
                                           runtime::LodOptions{.errorPx = 0.5});
    // Low over the lost patch's area, so its parent wants to split.
    const Camera c = camera(0.3, 0.3, 20.0, 0.35, 0.35);
    settle(c);
    ASSERT_TRUE(m_residency->hasFailed(lost));
    const io::PatchId parent{1, 0, 0};
    const bool parentDrawn = std::any_of(m_draws.begin(), m_draws.end(),
                                         [&](const PatchDraw& d) { return d.id == parent; });
    EXPECT_TRUE(parentDrawn) << "the parent of the failed patch draws in its place";
    for (const PatchDraw& d : m_draws) {
        for (io::PatchId up = d.id; up.level > lost.level;) {
            up = {up.level - 1, up.x / 2, up.y / 2};
            EXPECT_FALSE(up == lost) << "a descendant of the failed patch is drawn";
        }
    }
    EXPECT_GT(m_draws.size(), 4u) << "the rest of the view refines";
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
}

// Leaves that can never split — the finest level with the camera inside its box, or a
// patch whose child failed to load — once re-scheduled their own check at zero travel and
// a frame never ended. Every frame must end, and a still camera must cost nothing.
TEST_F(LodQuadtreeTest, UnsplittableLeavesDoNotRecheckWithinAFrame) {
    open({.fails = [](const io::PatchId& id) {
        return id.level > 1 && (id.x + 2 * id.y) % 3 == 0;
    }});
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface,
                                           runtime::LodOptions{.errorPx = 0.5});
    // Just above the highest sample: inside the bounding boxes of the patches below.
    Camera c = camera(0.5, 0.5, 0.5, 0.55, 0.55);
    c.position.z = m_geometry->maxHeight() - 1.0;
    settle(c);
    EXPECT_GT(m_residency->failed().size(), 0u);
    for (int i = 0; i < 10; ++i) {
        const LodUpdateStats s = frame(c);
        EXPECT_EQ(s.evaluations, 0u) << "frame " << i;
    }
    EXPECT_EQ(m_tree->checkInvariants(), std::nullopt);
}

// The tree pins what it holds and gives every pin back: no layer leaks when it goes.
TEST_F(LodQuadtreeTest, DestroyingTheTreeUnpinsEveryLayer) {
    m_tree = std::make_unique<LodQuadtree>(*m_residency, *m_surface,
                                           runtime::LodOptions{.errorPx = 1.0});
    const LodUpdateStats settled = settle(camera(0.2, 0.3, 300.0, 0.6, 0.5));
    EXPECT_EQ(m_residency->pinnedCount(), settled.nodes);
    EXPECT_GT(settled.nodes, settled.drawn);
    m_tree.reset();
    EXPECT_EQ(m_residency->pinnedCount(), 0u);
}

}  // namespace
}  // namespace terrain::test
