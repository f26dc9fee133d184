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
    const auto secondsSince = [&] {
        return std::chrono::duration<double>(Clock::now() - arrived).count();
    };
    std::uint64_t frames = 0;
    nlohmann::json heights, imagery;  // when each came to full detail
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
        // Each from the frame it came to full detail and stayed there (a finer patch may want
        // finer imagery again).
        if (waitingSplits > 0 || session.loadsOutstanding() > 0)
            heights = nullptr;
        else if (heights.is_null())
            heights = {{"frames", frames}, {"seconds", secondsSince()}};
        if (session.imageryWaiting() > 0)
            imagery = nullptr;
        else if (imagery.is_null())
            imagery = {{"frames", frames}, {"seconds", secondsSince()}};
        settled = !heights.is_null() && !imagery.is_null();
    }
    const double seconds = secondsSince();
    session.drain(std::chrono::seconds(10));
    if (!settled) return nlohmann::json();
    return nlohmann::json{
        {"frames", frames}, {"seconds", seconds}, {"heights", heights}, {"imagery", imagery}};
}

}  // namespace terrain::tools
