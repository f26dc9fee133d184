// StressTarget: one session and the flight of its surface.
#include "StressTarget.h"

#include "GlobeStressFlight.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/GlobeDrawnGround.h"
#include "terrain/runtime/GroundHeight.h"
#include "terrain/runtime/PlaneSurface.h"

namespace terrain::tools {

StressTarget::StressTarget(std::unique_ptr<SurfaceKit> kit,
                           std::unique_ptr<runtime::TerrainSession> session,
                           std::optional<io::GlobeGroundQuery> globeGround,
                           const StressTargetOptions& o)
    : m_kit(std::move(kit)), m_session(std::move(session)), m_globeGround(std::move(globeGround)) {
    if (m_kit->kind() == runtime::SurfaceKind::Plane) {
        const runtime::TerrainGeometry& geometry = runtime::planeGeometry(m_session->surface());
        // The ground from what is resident: the flight never needs a read.
        m_flight = std::make_unique<StressFlight>(geometry, o.seed, [this](double x, double y) {
            return runtime::conservativeGroundHeight(
                m_session->streamer(), runtime::planeGeometry(m_session->surface()), x, y);
        });
    } else {
        // The ground from the pyramid's finest patch (read on this thread, once each time the
        // flight crosses into another patch), or from what the last frame drew where that
        // read fails (a damaged patch is part of the test).
        m_flight = std::make_unique<GlobeStressFlight>(
            m_session->manifest(), o.seed, [this](const runtime::GlobePose& pose) {
                auto below = m_globeGround->at(pose.where.latitudeDeg, pose.where.longitudeDeg);
                return below ? below.value().heightM
                             : runtime::drawnGroundCeiling(m_session->draws(),
                                                           globe::Wgs84::toEcef(pose.where));
            });
    }
    if (o.cruiseSpeedAndAltitude)
        m_flight->cruise(o.cruiseSpeedAndAltitude->first, o.cruiseSpeedAndAltitude->second);
}

void StressTarget::beginFrame(double dtS, runtime::Camera& camera) {
    m_flight->step(dtS, camera);
    m_lod = m_session->beginFrame(camera);
}

Result<std::unique_ptr<StressTarget>> StressTarget::open(const StressTargetOptions& o) {
    if (runtime::lodMethodInfo(o.method).inCore)
        return Error{o.pyramid + ": --method " + std::string(runtime::lodMethodName(o.method)) +
                     " streams nothing (it reads the finest level once): the stress test flies "
                     "the streaming methods (every method but rtin, lee2011 and ripolles)"};
    auto manifest = io::readManifest(o.pyramid);
    if (!manifest) return manifest.error();
    std::unique_ptr<SurfaceKit> kit = SurfaceKit::of(manifest.value());
    if (Status supported = kit->supports(o.pyramid, o.method); !supported) return supported.error();
    runtime::TerrainSessionOptions options;
    options.method = o.method;
    options.streaming = o.streaming;
    options.lod = o.lod;
    auto session = runtime::TerrainSession::open(o.pyramid, options);
    if (!session) return session.error();
    std::optional<io::GlobeGroundQuery> ground;
    if (kit->kind() == runtime::SurfaceKind::Globe) {
        auto opened = io::GlobeGroundQuery::open(o.pyramid);
        if (!opened) return opened.error();
        ground = std::move(opened).value();
    }
    return std::unique_ptr<StressTarget>(
        new StressTarget(std::move(kit), std::move(session).value(), std::move(ground), o));
}

}  // namespace terrain::tools
