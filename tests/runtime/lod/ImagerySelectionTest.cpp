// runtime::ImagerySelection on fakes (no GL, one thread): a pixel finds texels as large as it
// is, the level follows the distance rather than the patch, a tile not resident yet is drawn
// from its finest resident ancestor's quadrant and asked for, and imagery finer than the DEM
// is listed below the DEM's finest level; a selection kept from frame to frame (its volumes
// cached) lists what a new one lists, on the globe, as the view and the heights change; each
// layer's coarsest tiles are the ones under the surface's roots.
#include "TestCameras.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeCamera.h"
#include "terrain/runtime/ImagerySelection.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <numbers>
#include <unordered_map>

namespace terrain::test {
namespace {

using runtime::ImageryNode;
using runtime::PatchDraw;

/// Every imagery tile exists down to the layer's finest level; resident as `resident` says,
/// on layer (level · 10^6 + x · 1000 + y) so a node's layer names its tile.
class FakeImagery final : public runtime::ImageryResidency {
public:
    explicit FakeImagery(int finestLevel) : m_finest(finestLevel) {}
    std::function<bool(const io::PatchId&)> resident = [](const io::PatchId&) { return true; };
    std::map<std::tuple<int, std::int64_t, std::int64_t>, float> wanted;

    static int layerOf(const io::PatchId& id) {
        return static_cast<int>(id.level * 1000000 + id.x * 1000 + id.y);
    }
    int imageryLayerCount() const override { return 1; }
    std::optional<int> gpuLayer(int, const io::PatchId& id) override {
        if (absent(id) || !resident(id)) return std::nullopt;
        return layerOf(id);
    }
    /// Read and found absent (the streamer keeps such a tile's info, never its texels).
    std::function<bool(const io::PatchId&)> absent = [](const io::PatchId&) { return false; };
    const io::ImageryTileInfo* tileInfo(int, const io::PatchId& id) const override {
        if (absent(id)) return &m_absent;
        if (!resident(id)) return nullptr;
        return id.level < m_finest ? &m_parent : &m_leaf;
    }
    void want(int, const io::PatchId& id, float priority) override {
        wanted[{id.level, id.x, id.y}] = priority;
    }
    bool hasFailed(int, const io::PatchId&) const override { return false; }

private:
    int m_finest;
    io::ImageryTileInfo m_parent{true, 0xF, true};
    io::ImageryTileInfo m_leaf{true, 0, true};
    io::ImageryTileInfo m_absent{false, 0, false};
};

/// A flat DEM at 0 m: every patch resident with that height.
class FlatHeights final : public runtime::TileResidency {
public:
    const io::PatchInfo* acquire(const io::PatchId&, float) override { return &m_info; }
    int layerOf(const io::PatchId&) const override { return 0; }
    bool hasFailed(const io::PatchId&) const override { return false; }
    void pin(const io::PatchId&) override {}
    void unpin(const io::PatchId&) override {}
    int capacity() const override { return 1 << 20; }
    const io::PatchInfo* residentInfo(const io::PatchId&) const override { return &m_info; }
    bool isPinned(const io::PatchId&) const override { return true; }

private:
    io::PatchInfo m_info{.present = true};
};

/// Heights resident down to `depth`, each patch's range a function of its id and of `epoch`
/// (heights that change between frames, as patches arrive and are evicted).
class ChangingHeights final : public runtime::TileResidency {
public:
    int depth = 0;
    int epoch = 0;
    const io::PatchInfo* acquire(const io::PatchId& id, float) override { return residentInfo(id); }
    int layerOf(const io::PatchId&) const override { return 0; }
    bool hasFailed(const io::PatchId&) const override { return false; }
    void pin(const io::PatchId&) override {}
    void unpin(const io::PatchId&) override {}
    int capacity() const override { return 1 << 20; }
    const io::PatchInfo* residentInfo(const io::PatchId& id) const override {
        if (id.level > depth) return nullptr;
        io::PatchInfo& info = m_infos[id];
        info.present = true;
        info.minHeight = static_cast<float>((id.x * 7 + id.y * 3 + id.level + epoch) % 11) * 300.0f;
        info.maxHeight = info.minHeight + 200.0f + 100.0f * static_cast<float>(epoch % 3);
        return &info;
    }
    bool isPinned(const io::PatchId&) const override { return true; }

private:
    mutable std::unordered_map<io::PatchId, io::PatchInfo, io::PatchIdHash> m_infos;
};

io::PyramidManifest globeManifestWithImagery(int faceLevels, int imageryBelowFaces) {
    auto layout = io::globeLayout(faceLevels);
    EXPECT_TRUE(layout);
    io::PyramidManifest m = io::PyramidManifest::forLayout(layout.value());
    m.formatVersion = io::PyramidManifest::kGlobeFormatVersion;
    m.globe = io::ManifestGlobe{};
    m.globe->faceFinestLevel = faceLevels;
    m.georeference.crsKind = io::CrsKind::Geographic;
    m.imagery.push_back({.name = "photo",
                         .kind = std::string(io::ManifestImageryLayer::kStoredKind),
                         .folder = "imagery/photo",
                         .input = "photo.tif",
                         .codec = "webp",
                         .coarsestLevel = io::ManifestGlobe::kLevelOffset + imageryBelowFaces,
                         .finestLevel = io::ManifestGlobe::kLevelOffset + faceLevels + 2,
                         .opacity = 1.0});
    return m;
}

class ImagerySelectionTest : public ::testing::Test {
protected:
    // 1025 × 1025 samples 10 m apart (finest level 3); one layer to level 7: imagery
    // 16 × finer than the DEM (texels 10 · 128 / 248 / 16 ≈ 0.32 m at its finest).
    void SetUp() override {
        m_manifest = io::PyramidManifest::forLayout(io::PyramidLayout::create(1025, 1025).value());
        m_manifest.georeference.pixelSizeX = m_manifest.georeference.pixelSizeY = 10.0;
        m_manifest.imagery.push_back({.name = "photo",
                                      .kind = std::string(io::ManifestImageryLayer::kStoredKind),
                                      .folder = "imagery/photo",
                                      .input = "photo.tif",
                                      .codec = "webp",
                                      .coarsestLevel = 0,
                                      .finestLevel = 7,
                                      .opacity = 0.5});
        m_surface = runtime::makeSurface(m_manifest);
    }

    /// Every finest patch of the DEM drawn (the uniform grid).
    std::vector<PatchDraw> finestPatches() const {
        std::vector<PatchDraw> draws;
        const io::PyramidLayout& layout = m_manifest.layout;
        const int level = layout.finestLevel();
        for (std::int64_t y = 0; y < layout.patchesY(level); ++y)
            for (std::int64_t x = 0; x < layout.patchesX(level); ++x)
                draws.push_back(
                    PatchDraw::ofTile({level, x, y}, 0, io::PatchInfo{.present = true}));
        return draws;
    }

    int deepestListed(const runtime::ImagerySelection& selection) const {
        int deepest = 0;
        for (const ImageryNode& n : selection.nodes()) deepest = std::max(deepest, n.level);
        return deepest;
    }

    runtime::Camera lookingDown(double aboveM) const {
        const runtime::TerrainGeometry& g = runtime::planeGeometry(*m_surface);
        return cameraOverDem(g, 0.5, 0.5, aboveM, 0.5, 0.5001);
    }

    io::PyramidManifest m_manifest;
    std::unique_ptr<runtime::Surface> m_surface;
    FlatHeights m_heights;
};

TEST_F(ImagerySelectionTest, ListedTexelsMatchThePixelsAndFollowTheDistance) {
    runtime::ImagerySelection selection(*m_surface, m_manifest);
    ASSERT_EQ(selection.layerCount(), 1);
    EXPECT_DOUBLE_EQ(selection.layerOpacity(0), 0.5);
    FakeImagery imagery(7);
    const std::vector<PatchDraw> draws = finestPatches();
    int previous = -1;
    for (const double above : {40000.0, 8000.0, 1500.0, 150.0}) {
        const runtime::Camera camera = lookingDown(above);
        selection.select(camera, draws, imagery, m_heights);
        ASSERT_EQ(selection.roots().size(), draws.size());
        // Texels of a tile of level l: 10 m · 128 / 248 / 2^(l − 3). Under the camera the
        // deepest listed tile's are no larger than a pixel seen from `above` (its nearest
        // point), unless it is the finest; its parent's were larger, or it would not be.
        const double pixelsPerRadian = camera.errorScale();
        const auto texelPx = [&](int level) {
            return 10.0 * 128.0 / 248.0 * std::ldexp(1.0, 3 - level) * pixelsPerRadian / above;
        };
        int underCamera = -1;
        for (const ImageryNode& n : selection.nodes()) {
            const std::int64_t at = std::int64_t{512} >> std::max(0, 10 - n.level);
            if (n.map[2] == 1.0f && n.gpuLayer == FakeImagery::layerOf({n.level, at, at}))
                underCamera = std::max(underCamera, n.level);
        }
        ASSERT_GE(underCamera, 0);
        if (underCamera < 7) {
            EXPECT_LE(texelPx(underCamera), 1.0) << "above " << above;
        }
        if (underCamera > 0) {
            EXPECT_GT(texelPx(underCamera - 1), 1.0) << "above " << above;
        }
        const int deepest = deepestListed(selection);
        EXPECT_GT(deepest, previous) << "closer must list finer imagery, above " << above;
        previous = deepest;
    }
    // 150 m over flat ground: the finest imagery (level 7, past the DEM's level 3) is listed.
    EXPECT_EQ(previous, 7);
}

TEST_F(ImagerySelectionTest, ATileNotResidentDrawsItsAncestorsQuadrantAndIsAskedFor) {
    runtime::ImagerySelection selection(*m_surface, m_manifest);
    FakeImagery imagery(7);
    imagery.resident = [](const io::PatchId& id) { return id.level <= 1; };
    const std::vector<PatchDraw> draws = finestPatches();
    selection.select(lookingDown(200.0), draws, imagery, m_heights);
    int fromAncestor = 0;
    for (const ImageryNode& n : selection.nodes()) {
        ASSERT_GE(n.gpuLayer, 0) << "a hole: no ancestor drawn at level " << n.level;
        if (n.level <= 1) {
            EXPECT_EQ(n.map[2], 1.0f);
            continue;
        }
        // A level-2 tile is drawn from its level-1 parent's quadrant and not expanded.
        ++fromAncestor;
        EXPECT_EQ(n.level, 2);
        EXPECT_EQ(n.map[2], 0.5f);
        EXPECT_EQ(n.children, -1);
        EXPECT_EQ(n.gpuLayer / 1000000, 1);
    }
    EXPECT_GT(fromAncestor, 0);
    for (const auto& [tile, priority] : imagery.wanted) {
        EXPECT_EQ(std::get<0>(tile), 2);
        EXPECT_GT(priority, 1.0f) << "its texels are larger than a pixel: why it is listed";
    }
    EXPECT_FALSE(imagery.wanted.empty());
}

TEST(ImagerySelectionPartialLayerTest, ARootKnownAbsentIsNeitherAskedForNorWaitedFor) {
    // 8193² samples (finest level 6): a finest patch's root lies 3 levels up, at level 3,
    // below the layer's coarsest. The layer reaches no further than its level-0 tile here
    // (a small image far away): its level-3 tiles were read and found absent. A frame then
    // draws the level-0 tile's quadrant, asks for nothing and waits for nothing (before, it
    // asked for the absent roots every frame, and a session never settled).
    io::PyramidManifest manifest =
        io::PyramidManifest::forLayout(io::PyramidLayout::create(8193, 8193).value());
    manifest.georeference.pixelSizeX = manifest.georeference.pixelSizeY = 10.0;
    manifest.imagery.push_back({.name = "inset",
                                .kind = std::string(io::ManifestImageryLayer::kStoredKind),
                                .folder = "imagery/inset",
                                .input = "inset.tif",
                                .codec = "webp",
                                .coarsestLevel = 0,
                                .finestLevel = 8,
                                .opacity = 1.0});
    const std::unique_ptr<runtime::Surface> surface = runtime::makeSurface(manifest);
    runtime::ImagerySelection selection(*surface, manifest);
    FakeImagery imagery(8);
    imagery.absent = [](const io::PatchId& id) { return id.level >= 1; };
    FlatHeights heights;
    std::vector<PatchDraw> draws;
    for (std::int64_t x = 30; x < 34; ++x)
        draws.push_back(PatchDraw::ofTile({6, x, 32}, 0, io::PatchInfo{.present = true}));
    const runtime::TerrainGeometry& g = runtime::planeGeometry(*surface);
    const runtime::ImagerySelectionStats stats =
        selection.select(cameraOverDem(g, 0.5, 0.5, 300.0, 0.5, 0.5001), draws, imagery, heights);
    EXPECT_TRUE(imagery.wanted.empty());
    EXPECT_EQ(stats.waiting, 0);
    for (const runtime::ImageryRoot& root : selection.roots()) {
        const ImageryNode& node = selection.nodes()[static_cast<std::size_t>(root.node)];
        EXPECT_EQ(node.level, 3);
        EXPECT_EQ(node.gpuLayer, FakeImagery::layerOf({0, 0, 0}));  // the level-0 tile's
        EXPECT_EQ(node.map[2], 0.125f);
    }
}

TEST_F(ImagerySelectionTest, RootsLieAboveThePatchOnItsLineOfAncestors) {
    runtime::ImagerySelection selection(*m_surface, m_manifest);
    FakeImagery imagery(7);
    const std::vector<PatchDraw> draws = finestPatches();  // level 3: roots at level 0
    selection.select(lookingDown(2000.0), draws, imagery, m_heights);
    for (std::size_t i = 0; i < draws.size(); ++i) {
        const runtime::ImageryRoot& root = selection.roots()[i];
        const ImageryNode& node = selection.nodes()[static_cast<std::size_t>(root.node)];
        EXPECT_EQ(node.level, 0);
        EXPECT_FLOAT_EQ(root.scale, 0.125f);
        EXPECT_FLOAT_EQ(root.offset[0], static_cast<float>(draws[i].id.x) * 0.125f);
        EXPECT_FLOAT_EQ(root.offset[1], static_cast<float>(draws[i].id.y) * 0.125f);
    }
    // Shared by id: one root node for all 64 patches.
    EXPECT_EQ(std::count_if(selection.nodes().begin(), selection.nodes().end(),
                            [](const ImageryNode& n) { return n.level == 0; }),
              1);
}

TEST(ImagerySelectionGlobeTest, AKeptSelectionListsWhatANewOneLists) {
    // Its volumes are cached across frames: a box kept for heights that have changed since,
    // or for another tile, would list other tiles or ask for them at other priorities.
    const io::PyramidManifest manifest = globeManifestWithImagery(10, 0);
    const std::unique_ptr<runtime::Surface> surface = runtime::makeSurface(manifest);
    const int drawnLevel = io::ManifestGlobe::kLevelOffset + 3;
    std::vector<PatchDraw> draws;
    for (const io::PatchId& root : surface->roots())
        for (std::int64_t y = 0; y < 8; ++y)
            for (std::int64_t x = 0; x < 8; ++x)
                draws.push_back(PatchDraw::ofTile({drawnLevel, root.x * 8 + x, root.y * 8 + y}, 0,
                                                  io::PatchInfo{.present = true}));
    // A few tiles below the roots not resident: drawn from an ancestor, asked for.
    const auto resident = [](const io::PatchId& id) {
        return id.level < io::ManifestGlobe::kLevelOffset + 4 ||
               (id.x + 2 * id.y + id.level) % 7 != 0;
    };
    FakeImagery keptImagery(manifest.imagery[0].finestLevel);
    FakeImagery newImagery(manifest.imagery[0].finestLevel);
    keptImagery.resident = newImagery.resident = resident;
    ChangingHeights heights;
    runtime::ImagerySelection kept(*surface, manifest);
    struct Frame {
        double latitude, longitude, heightM;
        int depth, epoch;
    };
    const Frame frames[] = {{46.0, 7.0, 4.0e6, 0, 0}, {46.0, 7.0, 4.0e5, 2, 0},
                            {46.1, 7.1, 4.0e4, 4, 1}, {46.1, 7.1, 4.0e4, 4, 2},
                            {46.2, 7.0, 3.0e3, 7, 2}, {-10.0, 120.0, 1.0e6, 3, 3},
                            {46.2, 7.0, 3.0e3, 7, 2}};
    int listed = 0;
    for (const Frame& f : frames) {
        SCOPED_TRACE(f.heightM);
        runtime::Camera camera;
        camera.viewportWidth = 960;
        camera.viewportHeight = 540;
        camera.fovY = 60.0 * std::numbers::pi / 180.0;
        runtime::placeOnGlobe(camera, {{f.latitude, f.longitude, f.heightM}, 30.0, -40.0});
        heights.depth = io::ManifestGlobe::kLevelOffset + f.depth;
        heights.epoch = f.epoch;
        keptImagery.wanted.clear();
        newImagery.wanted.clear();
        const runtime::ImagerySelectionStats keptStats =
            kept.select(camera, draws, keptImagery, heights);
        runtime::ImagerySelection fresh(*surface, manifest);
        const runtime::ImagerySelectionStats newStats =
            fresh.select(camera, draws, newImagery, heights);
        EXPECT_EQ(keptStats.nodes, newStats.nodes);
        EXPECT_EQ(keptStats.residentNodes, newStats.residentNodes);
        EXPECT_EQ(keptStats.wanted, newStats.wanted);
        EXPECT_EQ(keptStats.waiting, newStats.waiting);
        ASSERT_EQ(kept.nodes().size(), fresh.nodes().size());
        for (std::size_t i = 0; i < kept.nodes().size(); ++i) {
            const ImageryNode& a = kept.nodes()[i];
            const ImageryNode& b = fresh.nodes()[i];
            EXPECT_EQ(a.gpuLayer, b.gpuLayer) << i;
            EXPECT_EQ(a.children, b.children) << i;
            EXPECT_EQ(a.level, b.level) << i;
            EXPECT_EQ(a.map, b.map) << i;
        }
        ASSERT_EQ(kept.roots().size(), fresh.roots().size());
        for (std::size_t i = 0; i < kept.roots().size(); ++i) {
            EXPECT_EQ(kept.roots()[i].node, fresh.roots()[i].node) << i;
            EXPECT_EQ(kept.roots()[i].offset, fresh.roots()[i].offset) << i;
            EXPECT_EQ(kept.roots()[i].scale, fresh.roots()[i].scale) << i;
        }
        EXPECT_TRUE(std::equal(kept.children().begin(), kept.children().end(),
                               fresh.children().begin(), fresh.children().end()));
        EXPECT_EQ(keptImagery.wanted, newImagery.wanted);
        listed += keptStats.nodes;
    }
    EXPECT_GT(listed, 1000) << "too few tiles listed to compare";
}

TEST(ImagerySelectionGlobeTest, ALayersCoarsestTilesAreThoseUnderTheCubeFaces) {
    for (const int below : {0, 1}) {
        const io::PyramidManifest manifest = globeManifestWithImagery(6, below);
        const std::unique_ptr<runtime::Surface> surface = runtime::makeSurface(manifest);
        const runtime::ImagerySelection selection(*surface, manifest);
        const std::vector<io::PatchId> tiles = selection.coarsestTiles(0);
        ASSERT_EQ(tiles.size(), below == 0 ? 6u : 24u);
        for (const io::PatchId& tile : tiles) {
            EXPECT_EQ(tile.level, io::ManifestGlobe::kLevelOffset + below);
            const io::PatchId face{tile.level - below, tile.x >> below, tile.y >> below};
            EXPECT_NE(std::find(surface->roots().begin(), surface->roots().end(), face),
                      surface->roots().end());
        }
    }
}

TEST_F(ImagerySelectionTest, APlanesCoarsestTileIsItsRoot) {
    const runtime::ImagerySelection selection(*m_surface, m_manifest);
    const std::vector<io::PatchId> tiles = selection.coarsestTiles(0);
    ASSERT_EQ(tiles.size(), 1u);
    EXPECT_EQ(tiles[0], (io::PatchId{0, 0, 0}));
}

}  // namespace
}  // namespace terrain::test
