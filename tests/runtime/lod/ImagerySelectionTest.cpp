// runtime::ImagerySelection on fakes (no GL, one thread): a pixel finds texels as large as it
// is, the level follows the distance rather than the patch, a tile not resident yet is drawn
// from its finest resident ancestor's quadrant and asked for, and imagery finer than the DEM
// is listed below the DEM's finest level.
#include "TestCameras.h"
#include "terrain/runtime/ImagerySelection.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
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
        if (!resident(id)) return std::nullopt;
        return layerOf(id);
    }
    const io::ImageryTileInfo* tileInfo(int, const io::PatchId& id) const override {
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

}  // namespace
}  // namespace terrain::test
