// The imagery a session streams (issue 47), on the real streamer with fake imagery layers:
// the methods that draw with their own renderers (no imagery) select none and ask for none;
// the methods that drape it have every layer's coarsest tiles resident when open() returns,
// so the first frame wears imagery rather than the plain tint. Frames wait for reads, never
// sleep.
#include "FakeImagerySource.h"
#include "GlTestFixture.h"
#include "StreamingTestPyramid.h"
#include "TempFolder.h"
#include "TestCameras.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainSession.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

namespace terrain::runtime {
namespace {

namespace fs = std::filesystem;

class SessionImageryTest : public test::GlTest {
protected:
    void SetUp() override {
        test::GlTest::SetUp();
        m_pyramid = m_folder.path() / "imagery.pyramid";
        fs::copy(test::streamingTestPyramid(), m_pyramid, fs::copy_options::recursive);
        ASSERT_TRUE(test::addImageryLayers(m_pyramid, 2).ok());
    }

    TerrainSessionOptions optionsFor(LodMethod method) const {
        TerrainSessionOptions options;
        options.method = method;
        options.streaming.io.openImagery = test::fakeImageryOpener({});
        return options;
    }

    // High over the middle of the DEM, the whole of it in view.
    static Camera overTheDem(const TerrainSession& session) {
        const TerrainGeometry& g = planeGeometry(session.surface());
        return test::cameraOverDem(g, 0.5, 0.3, 0.4 * g.demSize().x, 0.5, 0.6);
    }

    test::TempFolder m_folder;
    fs::path m_pyramid;
};

TEST_F(SessionImageryTest, MethodsWithTheirOwnRenderersAskForNoImagery) {
    for (const LodMethod method :
         {LodMethod::Livny2007, LodMethod::Cdlod, LodMethod::Valdetaro2011}) {
        SCOPED_TRACE(lodMethodName(method));
        auto opened = TerrainSession::open(m_pyramid, optionsFor(method));
        ASSERT_TRUE(opened) << opened.error().message;
        TerrainSession& session = *opened.value();
        EXPECT_EQ(session.imagery(), nullptr);
        const Camera camera = overTheDem(session);
        // Frames until the heights' root is drawn, then a few more (these methods' splits
        // need not settle: settle() is not theirs to pass).
        int drawnFrames = 0;
        for (int frame = 0; frame < 10000 && drawnFrames < 4; ++frame) {
            session.beginFrame(camera);  // selects what the draw would wear
            if (!session.draws().empty()) ++drawnFrames;
            FrameTelemetry t;
            session.endFrame(t);
            session.streamer().waitForReads(std::chrono::seconds(10));
        }
        EXPECT_EQ(drawnFrames, 4);
        EXPECT_EQ(session.streamer().imagery().ledger().submitted, 0u);
    }
}

TEST_F(SessionImageryTest, TheFirstFrameFindsEveryLayersCoarsestTilesResident) {
    auto opened = TerrainSession::open(m_pyramid, optionsFor(LodMethod::Yusov2011));
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    ASSERT_NE(session.imagery(), nullptr);
    ASSERT_EQ(session.imagery()->layerCount(), 2);
    ImageryStreamer& imagery = session.streamer().imagery();
    // Before any frame: open() waited for them.
    for (int layer = 0; layer < 2; ++layer) {
        for (const io::PatchId& tile : session.imagery()->coarsestTiles(layer)) {
            EXPECT_EQ(tile, (io::PatchId{0, 0, 0}));
            EXPECT_TRUE(imagery.gpuLayer(layer, tile).has_value()) << "layer " << layer;
        }
    }
    // The first frame that draws the heights: every listed tile drawn from a tile of its own
    // or an ancestor's, none from nothing (the tint).
    const Camera camera = overTheDem(session);
    for (int frame = 0; frame < 10000; ++frame) {
        session.beginFrame(camera);
        if (!session.draws().empty()) break;
        FrameTelemetry t;
        session.endFrame(t);
        session.streamer().waitForReads(std::chrono::seconds(10));
    }
    ASSERT_FALSE(session.imagery()->nodes().empty());
    for (const ImageryNode& node : session.imagery()->nodes())
        EXPECT_GE(node.gpuLayer, 0) << "level " << node.level;
    for (int layer = 0; layer < 2; ++layer)
        EXPECT_TRUE(imagery.gpuLayer(layer, {0, 0, 0}).has_value());
    FrameTelemetry t;
    session.endFrame(t);
}

// imageryWaiting() is what terrain-render and terrain-bench time the imagery's full detail
// by: not 0 while the view's tiles are missing (drawn from the coarsest), 0 once settled;
// and 0 for a method that drapes no imagery.
TEST_F(SessionImageryTest, ImageryWaitingCountsTheTilesTheViewStillWants) {
    auto opened = TerrainSession::open(m_pyramid, optionsFor(LodMethod::Yusov2011));
    ASSERT_TRUE(opened) << opened.error().message;
    TerrainSession& session = *opened.value();
    const Camera camera = overTheDem(session);
    std::uint64_t mostWaiting = 0;
    for (int frame = 0; frame < 10000; ++frame) {
        session.beginFrame(camera);
        mostWaiting = std::max(mostWaiting, session.imageryWaiting());
        const bool drawn = !session.draws().empty();
        FrameTelemetry t;
        session.endFrame(t);
        if (drawn && mostWaiting > 0) break;
        session.streamer().waitForReads(std::chrono::seconds(10));
    }
    EXPECT_GT(mostWaiting, 0u);
    // Frames as a user would see them until every wanted tile is resident.
    bool arrived = false;
    for (int frame = 0; frame < 10000 && !arrived; ++frame) {
        session.beginFrame(camera);
        arrived = session.imageryWaiting() == 0;
        FrameTelemetry t;
        session.endFrame(t);
        if (!arrived) session.streamer().waitForReads(std::chrono::seconds(10));
    }
    EXPECT_TRUE(arrived);
    EXPECT_GT(session.imageryStats().residentNodes, 0);
    FrameTelemetry t;
    auto livny = TerrainSession::open(m_pyramid, optionsFor(LodMethod::Livny2007));
    ASSERT_TRUE(livny) << livny.error().message;
    livny.value()->beginFrame(camera);
    EXPECT_EQ(livny.value()->imageryWaiting(), 0u);
    livny.value()->endFrame(t);
}

}  // namespace
}  // namespace terrain::runtime
