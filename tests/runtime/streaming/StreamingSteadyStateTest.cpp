// The frame path allocates nothing once warm (issue 4: "no heap allocation per frame in
// steady state"): selection, streaming (CPU cache hits, GPU evictions and uploads through
// the ring) and the draw's instance records and uniforms, counted by the replaced global
// operator new on the render thread. Two views alternate over a GPU pool too small for
// both, so every switch evicts layers and uploads tiles again from the CPU cache.
// The draw call itself is counted apart: Mesa's tessellator allocates inside
// glDrawArraysInstanced, which is the driver's business, not the runtime's.
#include "AllocationCounter.h"
#include "GlTestFixture.h"
#include "StreamingTestPyramid.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"
#include "terrain/runtime/TileStreamer.h"

#include <epoxy/gl.h>

#include <chrono>
#include <vector>

namespace terrain::test {
namespace {

using runtime::Camera;

class StreamingSteadyStateTest : public GlTest {
protected:
    static Camera view(const runtime::TerrainGeometry& g, double fx, double fy, double tx,
                       double ty) {
        Camera c;
        c.viewportWidth = 320;
        c.viewportHeight = 240;
        c.fovY = 1.0;
        c.position = {g.worldAtFraction(fx, fy), g.maxHeight() + 100.0};
        c.lookAt({g.worldAtFraction(tx, ty), g.minHeight()});
        return c;
    }

    struct Loop {
        runtime::TileStreamer& streamer;
        const runtime::TerrainGeometry& geometry;
        runtime::TerrainRenderer& renderer;
        gl::Framebuffer& framebuffer;
        std::vector<runtime::PatchDraw> draws;
        runtime::FrameTelemetry telemetry;
        std::uint64_t driverAllocations = 0;  // inside the draw call

        void frame(const Camera& camera) {
            streamer.beginFrame();
            runtime::selectPatches(camera, geometry, 1.0, streamer, draws);
            framebuffer.clear({0.0f, 0.0f, 0.0f, 1.0f}, 0.0f);
            glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
            glViewport(0, 0, 320, 240);
            renderer.prepare(camera, streamer.pool(), draws, {}, 2.0);
            {
                const AllocationScope driver;
                renderer.submit(streamer.pool());
                driverAllocations += driver.allocations();
            }
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            streamer.endFrame(telemetry);
        }

        /// Frames of `camera` until nothing is outstanding; the GPU layers it then uses.
        int settle(const Camera& camera) {
            for (int i = 0; i < 3000; ++i) {
                frame(camera);
                if (i > 2 && streamer.loadsOutstanding() == 0) return streamer.pool().layersUsed();
                streamer.waitForReads(std::chrono::milliseconds(100));
            }
            ADD_FAILURE() << "the view never settled";
            return 0;
        }
    };

    static std::unique_ptr<runtime::TileStreamer> open(int gpuLayers) {
        runtime::TileStreamerOptions o;
        o.gpuLayers = gpuLayers;
        o.cpuCacheBytes = std::size_t{64} << 20;  // holds the whole test pyramid
        o.uploadBytesPerFrame = std::size_t{64} << 20;
        auto opened = runtime::TileStreamer::open(streamingTestPyramid(), o);
        EXPECT_TRUE(opened) << opened.error().message;
        return opened ? std::move(opened).value() : nullptr;
    }
};

TEST_F(StreamingSteadyStateTest, AlternatingViewsAllocateNothingOnceWarm) {
    // How many layers each view needs on its own, with room to spare.
    int layersA = 0, layersB = 0;
    {
        auto big = open(512);
        ASSERT_TRUE(big);
        const runtime::PlaneSurface surface(big->manifest());
        const runtime::TerrainGeometry& g = surface.geometry();
        auto renderer = runtime::TerrainRenderer::create(surface, 512);
        ASSERT_TRUE(renderer) << renderer.error().message;
        auto fb = gl::Framebuffer::create(320, 240);
        ASSERT_TRUE(fb);
        Loop loop{*big, g, renderer.value(), fb.value(), {}, {}};
        layersA = loop.settle(view(g, 0.1, 0.1, 0.4, 0.4));
        ASSERT_TRUE(big->drain(std::chrono::seconds(10)));
    }
    {
        auto big = open(512);
        ASSERT_TRUE(big);
        const runtime::PlaneSurface surface(big->manifest());
        const runtime::TerrainGeometry& g = surface.geometry();
        auto renderer = runtime::TerrainRenderer::create(surface, 512);
        ASSERT_TRUE(renderer) << renderer.error().message;
        auto fb = gl::Framebuffer::create(320, 240);
        ASSERT_TRUE(fb);
        Loop loop{*big, g, renderer.value(), fb.value(), {}, {}};
        layersB = loop.settle(view(g, 0.9, 0.9, 0.6, 0.6));
        ASSERT_TRUE(big->drain(std::chrono::seconds(10)));
    }
    ASSERT_GT(layersA, 8);
    ASSERT_GT(layersB, 8);

    // A pool that holds either view but not both.
    const int capacity = std::max(layersA, layersB) + 2;
    ASSERT_LT(capacity, layersA + layersB - 1);
    auto streamer = open(capacity);
    ASSERT_TRUE(streamer);
    const runtime::PlaneSurface surface(streamer->manifest());
    const runtime::TerrainGeometry& g = surface.geometry();
    auto renderer = runtime::TerrainRenderer::create(surface, capacity);
    ASSERT_TRUE(renderer) << renderer.error().message;
    auto fb = gl::Framebuffer::create(320, 240);
    ASSERT_TRUE(fb);
    Loop loop{*streamer, g, renderer.value(), fb.value(), {}, {}};
    loop.draws.reserve(static_cast<std::size_t>(capacity));
    const Camera a = view(g, 0.1, 0.1, 0.4, 0.4);
    const Camera b = view(g, 0.9, 0.9, 0.6, 0.6);
    for (int round = 0; round < 3; ++round) {  // warm: every tile read, every map grown
        loop.settle(a);
        loop.settle(b);
    }
    const auto requestsBefore = streamer->ledger().submitted;

    std::uint64_t uploads = 0, evictions = 0;
    loop.driverAllocations = 0;
    AllocationScope scope;
    for (int round = 0; round < 3; ++round) {
        for (const Camera* camera : {&a, &b}) {
            for (int i = 0; i < 4; ++i) {
                loop.frame(*camera);
                uploads += loop.telemetry.gpuUploads;
                evictions += loop.telemetry.gpuEvictions;
            }
        }
    }
    const std::uint64_t allocations = scope.allocations() - loop.driverAllocations;
    EXPECT_EQ(allocations, 0u) << "the warm frame path allocated";
    RecordProperty("driver_allocations_in_draw_calls", std::to_string(loop.driverAllocations));
    EXPECT_EQ(streamer->ledger().submitted, requestsBefore) << "every tile came from the CPU cache";
    EXPECT_GT(uploads, 0u) << "switching views must re-upload";
    EXPECT_GT(evictions, 0u) << "the pool cannot hold both views";
    EXPECT_EQ(streamer->checkInvariants(), std::nullopt);
    glFinish();
}

}  // namespace
}  // namespace terrain::test
