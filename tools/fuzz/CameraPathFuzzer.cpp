// Fuzz target: the camera path readers (CameraPath::load, GlobeCameraPath::load: JSON,
// keys, checks, spline tangents). Each reads the same input; each refuses the other's
// format by name. A path either reader accepts must play: every pose along it is finite.
#include "FuzzScratch.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/CameraPath.h"
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

template <typename Path>
void play(const Path& path) {
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
    if (auto planar = runtime::CameraPath::load(file)) play(planar.value());
    if (auto globe = runtime::GlobeCameraPath::load(file)) play(globe.value());
    return 0;
}
