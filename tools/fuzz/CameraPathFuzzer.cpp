// Fuzz target: the one camera path reader (FlightPath::load: JSON, keys, checks, spline
// tangents), read without a stated surface and as each surface's path. A file is accepted
// without a stated surface exactly when it is accepted as its own surface's path (never as
// both), and refused with that surface's words; a path it accepts must play: every pose along
// it is finite.
#include "FuzzScratch.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/FlightPath.h"
#include "terrain/runtime/GlobeCameraPath.h"

#include <cmath>
#include <cstdint>
#include <span>

namespace {

bool finite(const terrain::runtime::Camera& c) {
    return std::isfinite(c.position.x) && std::isfinite(c.position.y) &&
           std::isfinite(c.position.z) && std::isfinite(c.yaw) && std::isfinite(c.pitch) &&
           std::isfinite(c.fovY);
}

void play(const terrain::runtime::FlightPath& path) {
    terrain::runtime::Camera camera;
    for (int i = 0; i <= 8; ++i) {
        path.apply(path.startS() + path.durationS() * i / 8.0, camera);
        terrain::fuzz::require(finite(camera), "an accepted camera path plays finite poses");
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    using namespace terrain;
    const auto seeds = fuzz::seedFolder();
    if (!seeds) return 0;
    runtime::CameraKeyframe low{0.0, {10.0, 20.0, 300.0}, std::nullopt, 0.3, -0.2, 60.0};
    runtime::CameraKeyframe looking{4.0, {500.0, 80.0, 900.0}, glm::dvec3{0.0, 0.0, 0.0}, 0.0, 0.0,
                                    45.0};
    runtime::CameraKeyframe high{9.5, {900.0, -40.0, 2000.0}, std::nullopt, -2.0, -1.0, 70.0};
    auto planar = runtime::CameraPath::fromKeyframes({low, looking, high});
    if (!planar) fuzz::harnessFailure(planar.error().message);
    if (auto saved = planar.value().save(*seeds / "planar.camera.json"); !saved)
        fuzz::harnessFailure(saved.error().message);
    const auto globe = runtime::GlobeCameraPath::fromOrbit(46.85, -121.76, 1.0, 12.0);
    if (auto saved = globe.save(*seeds / "globe.camera.json"); !saved)
        fuzz::harnessFailure(saved.error().message);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace terrain;
    const fuzz::fs::path file = fuzz::scratch() / "input.camera.json";
    fuzz::writeFile(file, std::span(data, size));
    const auto either = runtime::FlightPath::load(file);
    const auto planar = runtime::FlightPath::load(file, runtime::PathFrame::Plane);
    const auto globe = runtime::FlightPath::load(file, runtime::PathFrame::Globe);
    fuzz::require(!(planar.ok() && globe.ok()), "a camera path file is of one surface only");
    if (either) {
        const bool ownSurface =
            either.value().frame() == runtime::PathFrame::Plane ? planar.ok() : globe.ok();
        fuzz::require(ownSurface, "a path read without a stated surface reads as its own");
        play(either.value());
    } else {
        fuzz::require(!planar.ok() && !globe.ok(),
                      "a path refused without a stated surface is refused on both");
        fuzz::require(either.error().message == planar.error().message ||
                          either.error().message == globe.error().message,
                      "a path refused without a stated surface is refused in its surface's words");
    }
    return 0;
}
