// StressTarget: what terrain-stress flies and checks, on either surface: the runtime's session
// (TerrainSession), the seeded flight over it (the surface's camera conventions: StressFlight
// on the plane, GlobeStressFlight on the globe) and the per-frame invariants (StressChecks).
// The frame loop, the budgets, the telemetry and the report in main.cpp are the same for both.
#pragma once

#include "StressChecks.h"
#include "StressFlight.h"
#include "SurfaceKit.h"
#include "terrain/base/Result.h"
#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameTelemetry.h"
#include "terrain/runtime/LodMethod.h"
#include "terrain/runtime/TerrainSession.h"
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
    /// The LOD's options (ε, the reading ahead), the session's defaults where not set.
    runtime::LodOptions lod = runtime::TerrainSessionOptions{}.lod;
    /// A LOD method that streams (LodMethod.h); the RTIN, which streams nothing, is refused.
    runtime::LodMethod method = runtime::LodMethod::Yusov2011;
    std::uint64_t seed = 1;
    /// A steady cruise at this speed and height above the ground instead of the random
    /// flight; nullopt: the random flight.
    std::optional<std::pair<double, double>> cruiseSpeedAndAltitude;
};

/// Render thread only.
class StressTarget {
public:
    /// Opens the pyramid's session and the flight its surface calls for. Errors: the pyramid
    /// cannot be opened (named by the reader), or the method does not stream, or does not draw
    /// the pyramid's surface (its SurfaceKit's refusal).
    static Result<std::unique_ptr<StressTarget>> open(const StressTargetOptions& options);

    runtime::TileStreamer& streamer() { return m_session->streamer(); }
    /// "planar" or "globe".
    std::string_view tiling() const { return m_kit->tiling(); }
    std::uint64_t teleports() const { return m_flight->teleports(); }

    /// Moves the camera by `dtS` along the flight (which reads the ground before the frame),
    /// then the LOD update.
    void beginFrame(double dtS, runtime::Camera& camera);
    void draw(const runtime::Camera& camera, const runtime::TerrainStyle& style) {
        m_session->draw(camera, style);
    }
    void endFrame(runtime::FrameTelemetry& telemetry) { m_session->endFrame(telemetry); }
    /// The frame's invariants (StressChecks::afterFrame): the first violation, or nullopt.
    std::optional<std::string> check(StressChecks& checks) {
        return checks.afterFrame(*m_session, m_lod);
    }
    /// The end of the run: the LOD lets go of every layer it holds (pins included).
    void releaseLod() { m_session->restartLod(); }

private:
    StressTarget(std::unique_ptr<SurfaceKit> kit, std::unique_ptr<runtime::TerrainSession> session,
                 std::optional<io::GlobeGroundQuery> globeGround, const StressTargetOptions& o);

    std::unique_ptr<SurfaceKit> m_kit;
    std::unique_ptr<runtime::TerrainSession> m_session;
    std::optional<io::GlobeGroundQuery> m_globeGround;  // the globe's flight reads the ground
    std::unique_ptr<SeededFlight> m_flight;
    runtime::LodUpdateStats m_lod;
};

}  // namespace terrain::tools
