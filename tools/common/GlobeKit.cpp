// GlobeKit: the globe's side of SurfaceKit: the flight over a globe pyramid, its frame
// times, look and report fields.
#include "GlobeKit.h"
#include "SurfaceKit.h"

#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeCamera.h"

#include <algorithm>
#include <cmath>

namespace terrain::tools {

Result<GlobeFlightTarget> globeFlightTarget(const std::filesystem::path& pyramid) {
    auto query = io::GlobeGroundQuery::open(pyramid);
    if (!query) return query.error();
    const std::optional<io::ManifestGlobe>& g = query.value().reader().manifest().globe;
    // The extent's centre; west > east means it crosses the antimeridian.
    const double span = g->east >= g->west ? g->east - g->west : g->east + 360.0 - g->west;
    GlobeFlightTarget target;
    target.latitudeDeg = 0.5 * (g->south + g->north);
    target.longitudeDeg = std::remainder(g->west + 0.5 * span, 360.0);
    auto ground = query.value().at(target.latitudeDeg, target.longitudeDeg);
    if (!ground) return ground.error();
    target.groundM = ground.value().heightM;
    target.groundLevel = ground.value().faceLevel;
    return target;
}

Result<runtime::GlobeCameraPath> globeOrbitFlight(const std::filesystem::path& pyramid,
                                                  double durationS, double clearanceM) {
    auto found = globeFlightTarget(pyramid);
    if (!found) return found.error();
    return runtime::GlobeCameraPath::fromOrbit(found.value().latitudeDeg,
                                               found.value().longitudeDeg,
                                               found.value().groundM + clearanceM, durationS);
}

namespace {

// The globe: a globe camera path (or the fixed pose of GlobeFlags, or the flight from orbit),
// frames spread over the whole path, space for a sky and no fog.
class GlobeKit final : public SurfaceKit {
public:
    runtime::SurfaceKind kind() const override { return runtime::SurfaceKind::Globe; }
    runtime::PathFrame pathFrame() const override { return runtime::PathFrame::Globe; }

    Result<runtime::FlightPath> flight(const std::string& pyramid,
                                       const runtime::Surface& /*surface*/,
                                       const std::string& pathFile, double durationS,
                                       const GlobeFlags& globe) const override {
        if (globe.fixedPose()) {
            // One keyframe: the pose given, the data's centre where --lat or --lon is not.
            auto found = globeFlightTarget(pyramid);
            if (!found) return found.error();
            auto pose = runtime::GlobeCameraPath::fromKeyframes(
                {{0.0,
                  {{globe.latitudeDeg.value_or(found.value().latitudeDeg),
                    globe.longitudeDeg.value_or(found.value().longitudeDeg),
                    globe.heightM.value_or(runtime::GlobeCameraPath::kOrbitHeightM)},
                   globe.headingDeg,
                   globe.pitchDeg},
                  runtime::GlobeCameraPath::kDefaultFovYDegrees}});
            if (!pose) return pose.error();
            return runtime::FlightPath(std::move(pose).value());
        }
        if (!pathFile.empty()) return runtime::FlightPath::load(pathFile, pathFrame());
        auto orbit = globeOrbitFlight(pyramid, durationS);
        if (!orbit) return orbit.error();
        return runtime::FlightPath(std::move(orbit).value());
    }

    double frameTimeS(const runtime::FlightPath& path, std::uint64_t frame, std::uint64_t frames,
                      double /*fps*/) const override {
        const double fraction = frames > 1 ? double(frame) / double(frames - 1) : 0.0;
        return path.startS() + fraction * path.durationS();
    }

    void skyAndFog(runtime::TerrainStyle& style, const DrawStyleFlags& /*look*/,
                   const runtime::Surface& /*surface*/) const override {
        const std::array<float, 4> space = measureBackground();
        style.skyColor = {space[0], space[1], space[2]};  // no fog
    }

    double cameraHeightM(const runtime::Camera& camera) const override {
        return runtime::globePoseOf(camera).where.height;
    }

    std::array<float, 4> measureBackground() const override {
        return {0.02f, 0.03f, 0.08f, 1.0f};  // space
    }

    std::string_view rootFaultMessage() const override {
        return "a cube face's data cannot be drawn, its root patch failed: ";
    }

    bool measuresArrival() const override { return true; }

    void addJsonFields(nlohmann::json& out, const FlightFacts& facts) const override;
};

void GlobeKit::addJsonFields(nlohmann::json& out, const FlightFacts& facts) const {
    out["path"] = facts.fixedPose          ? nlohmann::json("fixed pose")
                  : facts.pathFile.empty() ? nlohmann::json("default")
                                           : nlohmann::json(facts.pathFile);
    const runtime::GlobePose endPose = runtime::globePoseOf(facts.lastCamera);
    out["end_pose"] = {{"latitude_deg", endPose.where.latitudeDeg},
                       {"longitude_deg", endPose.where.longitudeDeg},
                       {"height_m", endPose.where.height}};
    // The last frame's draw list by face level: data, virtual and bare patches, largest Err(P).
    nlohmann::json byLevel = nlohmann::json::object();
    for (const runtime::PatchDraw& d : facts.lastDraws) {
        nlohmann::json& level = byLevel[std::to_string(io::globePatchOf(d.id).level)];
        if (level.is_null())
            level = {{"data", 0}, {"virtual", 0}, {"bare", 0}, {"max_error_m", 0.0}};
        const char* kind = d.layer < 0 ? "bare" : d.isVirtual ? "virtual" : "data";
        level[kind] = level.value(kind, 0) + 1;
        level["max_error_m"] = std::max(level.value("max_error_m", 0.0), double(d.errorM));
    }
    out["last_frame_patches_by_level"] = byLevel;
    out["full_detail_after_arrival"] = facts.arrival;
    out["horizon_culling"] = facts.horizonCulling;
    out["horizon_culled_fraction_of_visited"] =
        facts.visited > 0 ? double(facts.horizonCulled) / double(facts.visited) : 0.0;
}

}  // namespace

std::unique_ptr<SurfaceKit> makeGlobeKit() { return std::make_unique<GlobeKit>(); }

}  // namespace terrain::tools
