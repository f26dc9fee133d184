#include "FullDetailAfterArrival.h"

#include "FullDetailClock.h"

#include "terrain/runtime/LodStrategyFactory.h"

#include <epoxy/gl.h>

#include <cstdint>

namespace terrain::tools {

Result<nlohmann::json> fullDetailAfterArrival(const std::string& pyramid,
                                              const runtime::TerrainSessionOptions& options,
                                              const runtime::Camera& camera,
                                              gl::Framebuffer& target, std::chrono::seconds limit) {
    auto fresh = runtime::openLodStrategy(pyramid, options);
    if (!fresh) return fresh.error();
    runtime::LodStrategy& session = *fresh.value();
    FullDetailClock clock;
    while (!clock.reached() && clock.seconds() < static_cast<double>(limit.count())) {
        clock.waitForNextFrame();
        const std::uint64_t waitingSplits = session.beginFrame(camera).waitingSplits;
        target.clear({0.0f, 0.0f, 0.0f, 1.0f}, 0.0f);
        glBindFramebuffer(GL_FRAMEBUFFER, target.id());
        glViewport(0, 0, camera.viewportWidth, camera.viewportHeight);
        session.draw(camera, runtime::TerrainStyle{});
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        runtime::FrameTelemetry ignored;
        session.endFrame(ignored);
        clock.frameEnded(session, waitingSplits);
    }
    nlohmann::json result = clock.result();
    session.drain(std::chrono::seconds(10));
    return result;
}

}  // namespace terrain::tools
