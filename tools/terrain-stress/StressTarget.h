// StressTarget: what terrain-stress flies and checks, for either kind of pyramid: the
// runtime's session (TerrainSession on a plane, GlobeSession on a globe), the seeded flight
// over it (StressFlight, GlobeStressFlight) and the per-frame invariants that fit its LOD
// (StressChecks). The frame loop, the budgets, the telemetry and the report in main.cpp are
// the same for both.
#pragma once

#include "StressChecks.h"
#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/LodMethod.h"
#include "terrain/runtime/TerrainRenderer.h"
#include "terrain/runtime/TileStreamer.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace terrain::tools {

struct StressTargetOptions {
    std::string pyramid;
    runtime::TileStreamerOptions streaming;
    double errorPx = 1.0;
    /// A LOD method that streams (LodMethod.h); the RTIN, which streams nothing, is refused.
    runtime::LodMethod method = runtime::LodMethod::Yusov2011;
    std::uint64_t seed = 1;
    /// A steady cruise at this speed and height above the ground instead of the random
    /// flight; nullopt: the random flight.
    std::optional<std::pair<double, double>> cruiseSpeedAndAltitude;
};

class StressTarget {
public:
    /// Opens the pyramid as the session its manifest calls for. Errors: the pyramid cannot
    /// be opened (named by the reader).
    static Result<std::unique_ptr<StressTarget>> open(const StressTargetOptions& options);
    virtual ~StressTarget() = default;

    virtual runtime::TileStreamer& streamer() = 0;
    /// "planar" or "globe".
    virtual std::string_view tiling() const = 0;
    virtual std::uint64_t teleports() const = 0;

    /// Moves the camera by `dtS` along the flight (which reads the ground before the frame),
    /// then the LOD update.
    virtual void beginFrame(double dtS, runtime::Camera& camera) = 0;
    virtual void draw(const runtime::Camera& camera, const runtime::TerrainStyle& style) = 0;
    virtual void endFrame(runtime::FrameTelemetry& telemetry) = 0;
    /// The frame's invariants (StressChecks::afterFrame or afterGlobeFrame): the first
    /// violation, or nullopt.
    virtual std::optional<std::string> check(StressChecks& checks) = 0;
    /// The end of the run: the LOD lets go of every layer it holds (pins included).
    virtual void releaseLod() = 0;
};

}  // namespace terrain::tools
