// StressTarget: the planar and the globe session behind one frame loop.
#include "StressTarget.h"

#include "GlobeStressFlight.h"
#include "StressFlight.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/GlobeDrawnGround.h"
#include "terrain/runtime/GlobeSession.h"
#include "terrain/runtime/GroundHeight.h"
#include "terrain/runtime/TerrainSession.h"

namespace terrain::tools {
namespace {

class PlanarStressTarget final : public StressTarget {
public:
    PlanarStressTarget(std::unique_ptr<runtime::TerrainSession> session,
                       const StressTargetOptions& o)
        : m_session(std::move(session)),
          // The ground from what is resident: the flight never needs a read.
          m_flight(m_session->geometry(), o.seed, [this](double x, double y) {
              return runtime::conservativeGroundHeight(m_session->streamer(), m_session->geometry(),
                                                       x, y);
          }) {
        if (o.cruiseSpeedAndAltitude)
            m_flight.cruise(o.cruiseSpeedAndAltitude->first, o.cruiseSpeedAndAltitude->second);
    }

    runtime::TileStreamer& streamer() override { return m_session->streamer(); }
    void releaseLod() override { m_session->restartLod(); }
    std::string_view tiling() const override { return "planar"; }
    std::uint64_t teleports() const override { return m_flight.teleports(); }
    void beginFrame(double dtS, runtime::Camera& camera) override {
        m_flight.step(dtS, camera);
        m_lod = m_session->beginFrame(camera);
    }
    void draw(const runtime::Camera& camera, const runtime::TerrainStyle& style) override {
        m_session->draw(camera, style);
    }
    void endFrame(runtime::FrameTelemetry& telemetry) override { m_session->endFrame(telemetry); }
    std::optional<std::string> check(StressChecks& checks) override {
        return checks.afterFrame(m_session->streamer(), m_session->tree(), m_session->draws(),
                                 m_lod);
    }

private:
    std::unique_ptr<runtime::TerrainSession> m_session;
    StressFlight m_flight;
    runtime::LodUpdateStats m_lod;
};

class GlobeStressTarget final : public StressTarget {
public:
    GlobeStressTarget(std::unique_ptr<runtime::GlobeSession> session, io::GlobeGroundQuery ground,
                      const io::PyramidManifest& manifest, const StressTargetOptions& o)
        : m_session(std::move(session)),
          m_ground(std::move(ground)),
          // The ground from the pyramid's finest patch (read on this thread, once each time
          // the flight crosses into another patch), or from what the last frame drew where
          // that read fails (a damaged patch is part of the test).
          m_flight(manifest, o.seed, [this](const runtime::GlobePose& pose) {
              auto below = m_ground.at(pose.where.latitudeDeg, pose.where.longitudeDeg);
              return below ? below.value().heightM
                           : runtime::drawnGroundCeiling(m_session->draws(),
                                                         globe::Wgs84::toEcef(pose.where));
          }) {
        if (o.cruiseSpeedAndAltitude)
            m_flight.cruise(o.cruiseSpeedAndAltitude->first, o.cruiseSpeedAndAltitude->second);
    }

    runtime::TileStreamer& streamer() override { return m_session->streamer(); }
    void releaseLod() override {}  // the globe LOD selects from the roots and pins nothing
    std::string_view tiling() const override { return "globe"; }
    std::uint64_t teleports() const override { return m_flight.teleports(); }
    void beginFrame(double dtS, runtime::Camera& camera) override {
        m_flight.step(dtS, camera);
        m_lod = m_session->beginFrame(camera);
    }
    void draw(const runtime::Camera& camera, const runtime::TerrainStyle& style) override {
        m_session->draw(camera, style);
    }
    void endFrame(runtime::FrameTelemetry& telemetry) override { m_session->endFrame(telemetry); }
    std::optional<std::string> check(StressChecks& checks) override {
        return checks.afterGlobeFrame(m_session->streamer(), m_session->draws(), m_lod);
    }

private:
    std::unique_ptr<runtime::GlobeSession> m_session;
    io::GlobeGroundQuery m_ground;
    GlobeStressFlight m_flight;
    runtime::GlobeLodStats m_lod;
};

}  // namespace

Result<std::unique_ptr<StressTarget>> StressTarget::open(const StressTargetOptions& o) {
    auto manifest = io::readManifest(o.pyramid);
    if (!manifest) return manifest.error();
    if (runtime::lodMethodInfo(o.method).inCore)
        return Error{o.pyramid + ": --method " + std::string(runtime::lodMethodName(o.method)) +
                     " streams nothing (it reads the finest level once): the stress test flies "
                     "the streaming methods (every method but rtin, lee2011 and ripolles)"};
    if (manifest.value().globe && o.method != runtime::LodMethod::Yusov2011)
        return Error{o.pyramid + ": a globe pyramid; only yusov2011 draws globes (--method " +
                     std::string(runtime::lodMethodName(o.method)) +
                     " compares on planar pyramids)"};
    if (!manifest.value().globe) {
        runtime::TerrainSessionOptions options;
        options.method = o.method;
        options.streaming = o.streaming;
        options.lod.errorPx = o.errorPx;
        auto session = runtime::TerrainSession::open(o.pyramid, options);
        if (!session) return session.error();
        return std::unique_ptr<StressTarget>(
            std::make_unique<PlanarStressTarget>(std::move(session).value(), o));
    }
    runtime::GlobeSessionOptions options;
    options.streaming = o.streaming;
    options.lod.errorPx = o.errorPx;
    auto session = runtime::GlobeSession::open(o.pyramid, options);
    if (!session) return session.error();
    auto ground = io::GlobeGroundQuery::open(o.pyramid);
    if (!ground) return ground.error();
    return std::unique_ptr<StressTarget>(std::make_unique<GlobeStressTarget>(
        std::move(session).value(), std::move(ground).value(), manifest.value(), o));
}

}  // namespace terrain::tools
