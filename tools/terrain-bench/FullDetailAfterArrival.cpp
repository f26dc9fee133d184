#include "FullDetailAfterArrival.h"

#include "terrain/runtime/LodStrategyFactory.h"

#include <epoxy/gl.h>

#include <cstdint>

namespace terrain::tools {

Result<nlohmann::json> fullDetailAfterArrival(const std::string& pyramid,
                                              const runtime::TerrainSessionOptions& options,
                                              const runtime::Camera& camera,
                                              gl::Framebuffer& target, std::chrono::seconds limit) {
    using Clock = std::chrono::steady_clock;
    auto fresh = runtime::openLodStrategy(pyramid, options);
    if (!fresh) return fresh.error();
    runtime::LodStrategy& session = *fresh.value();
    const auto arrived = Clock::now();
    std::uint64_t frames = 0;
    bool settled = false;
    while (!settled && Clock::now() - arrived < limit) {
        const std::uint64_t waitingSplits = session.beginFrame(camera).waitingSplits;
        target.clear({0.0f, 0.0f, 0.0f, 1.0f}, 0.0f);
        glBindFramebuffer(GL_FRAMEBUFFER, target.id());
        glViewport(0, 0, camera.viewportWidth, camera.viewportHeight);
        session.draw(camera, runtime::TerrainStyle{});
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        runtime::FrameTelemetry ignored;
        session.endFrame(ignored);
        ++frames;
        settled = waitingSplits == 0 && session.loadsOutstanding() == 0;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - arrived).count();
    session.drain(std::chrono::seconds(10));
    if (!settled) return nlohmann::json();
    return nlohmann::json{{"frames", frames}, {"seconds", seconds}};
}

}  // namespace terrain::tools
