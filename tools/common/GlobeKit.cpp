// GlobeKit: the globe's side of SurfaceKit: the flight over a globe pyramid, its frame
// times, look and report fields.
#include "GlobeKit.h"

#include "SurfaceKit.h"
#include "terrain/pyramid/NativeTiles.h"

#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/GlobeCamera.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace terrain::tools {

Result<GlobeFlightPlan> globeFlightPlan(const std::filesystem::path& pyramid,
                                        std::optional<int> visit) {
    auto query = io::GlobeGroundQuery::open(pyramid);
    if (!query) return query.error();
    const io::PyramidManifest& manifest = query.value().reader().manifest();
    GlobeFlightPlan plan;
    plan.tour = planGlobeTour(*manifest.globe);
    plan.visit = visit;
    plan.inputCount = manifest.source.inputs.size();
    const std::size_t places = plan.tour.places.size();
    if (visit && (*visit < 1 || std::size_t(*visit) > places))
        return Error{fmt::format("{}: --visit {}: the default flight visits {} {} (1{})",
                                 pyramid.string(), *visit, places, places == 1 ? "place" : "places",
                                 places == 1 ? "" : fmt::format(" … {}", places))};
    for (std::size_t i = 0; i < places; ++i) {
        if (visit && std::size_t(*visit) != i + 1) continue;
        const GlobeTourPlace& place = plan.tour.places[i];
        auto ground = query.value().at(place.latitudeDeg, place.longitudeDeg);
        if (!ground) return ground.error();
        plan.stops.push_back({place, ground.value().heightM, ground.value().faceLevel});
    }
    return plan;
}

runtime::GlobeCameraPath globeTourFlight(const GlobeFlightPlan& plan, double durationS,
                                         double clearanceM) {
    std::vector<runtime::GlobeTourStop> stops;
    for (const GlobeFlightStop& s : plan.stops)
        stops.push_back({s.place.latitudeDeg, s.place.longitudeDeg, s.groundM + clearanceM});
    return runtime::GlobeCameraPath::fromTour(stops, durationS);
}

namespace {

// "46.50° N, 121.50° W".
std::string whereText(double latitudeDeg, double longitudeDeg) {
    return fmt::format("{:.2f}° {}, {:.2f}° {}", std::abs(latitudeDeg),
                       latitudeDeg < 0.0 ? 'S' : 'N', std::abs(longitudeDeg),
                       longitudeDeg < 0.0 ? 'W' : 'E');
}

// A place's sources by file name: "N57E011.hgt", "N57E011.hgt + 3 more".
std::string namesText(const std::vector<std::string>& inputs) {
    if (inputs.empty()) return "the data";
    const std::string first = std::filesystem::path(inputs.front()).filename().string();
    return inputs.size() == 1 ? first : fmt::format("{} + {} more", first, inputs.size() - 1);
}

std::string placeText(const GlobeTourPlace& place) {
    return fmt::format("{} ({})", namesText(place.inputs),
                       whereText(place.latitudeDeg, place.longitudeDeg));
}

}  // namespace

std::string describeFlightPlan(const GlobeFlightPlan& plan, double durationS) {
    const std::vector<GlobeTourPlace>& places = plan.tour.places;
    std::string line;
    if (!plan.tour.perSource) {
        line = fmt::format("the default flight goes to the centre of the data ({})",
                           whereText(places.front().latitudeDeg, places.front().longitudeDeg));
        if (plan.inputCount > 1)
            line += fmt::format(
                ", the finest of its {} sources: the manifest records no other source's extent "
                "(rebuild the pyramid with this terrain-build to visit each, or give --lat and "
                "--lon)",
                plan.inputCount);
        return line;
    }
    if (plan.visit) {
        line = fmt::format("the flight goes to place {} of {} (--visit {}): {}", *plan.visit,
                           places.size(), *plan.visit,
                           placeText(places[std::size_t(*plan.visit - 1)]));
        if (places.size() > 1)
            line += fmt::format("; without --visit it visits all {} in turn", places.size());
    } else if (places.size() == 1) {
        line = "the default flight goes to " + placeText(places.front());
    } else {
        line = fmt::format("the default flight visits {} places, {:.3g} s each:", places.size(),
                           durationS / double(places.size()));
        for (std::size_t i = 0; i < places.size(); ++i)
            line += fmt::format("{} {}. {}", i == 0 ? "" : ",", i + 1, placeText(places[i]));
    }
    if (!plan.tour.global.empty())
        line += fmt::format("; it passes over {} (global)", namesText(plan.tour.global));
    if (!plan.visit && places.size() > 1) line += "; --visit N flies to place N only";
    return line;
}

nlohmann::json flightPlanJson(const GlobeFlightPlan& plan, double durationS) {
    nlohmann::json visits = nlohmann::json::array();
    for (std::size_t i = 0; i < plan.stops.size(); ++i) {
        const GlobeFlightStop& s = plan.stops[i];
        visits.push_back({{"inputs", s.place.inputs},
                          {"latitude_deg", s.place.latitudeDeg},
                          {"longitude_deg", s.place.longitudeDeg},
                          {"extent", {s.place.west, s.place.south, s.place.east, s.place.north}},
                          {"ground_m", s.groundM},
                          {"ground_level", s.groundLevel},
                          {"arrival_s", runtime::GlobeCameraPath::tourArrivalS(i, plan.stops.size(),
                                                                               durationS)}});
    }
    return {{"flight_visits", std::move(visits)},
            {"flight_passes_over", plan.tour.global},
            {"flight_visit", plan.visit ? nlohmann::json(*plan.visit) : nlohmann::json()},
            {"flight_places", plan.tour.places.size()}};
}

namespace {

// The globe: a globe camera path (or the fixed pose of GlobeFlags, or the flight from orbit),
// frames spread over the whole path, space for a sky and no fog.
class GlobeKit final : public SurfaceKit {
public:
    runtime::SurfaceKind kind() const override { return runtime::SurfaceKind::Globe; }
    runtime::PathFrame pathFrame() const override { return runtime::PathFrame::Globe; }

    Result<Flight> flight(const std::string& pyramid, const runtime::Surface& /*surface*/,
                          const std::string& pathFile, double durationS,
                          const GlobeFlags& globe) const override {
        if (!pathFile.empty() && globe.visit)
            return Error{
                fmt::format("{}: --visit picks a place of the default flight; --path {} "
                            "gives a flight of its own",
                            pyramid, pathFile)};
        if (globe.fixedPose()) {
            // One keyframe: the pose given, the place's centre (the --visit one, else the
            // tour's first) where --lat or --lon is not.
            auto plan = globeFlightPlan(pyramid, globe.visit.value_or(1));
            if (!plan) return plan.error();
            const GlobeTourPlace& place = plan.value().stops.front().place;
            auto pose = runtime::GlobeCameraPath::fromKeyframes(
                {{0.0,
                  {{globe.latitudeDeg.value_or(place.latitudeDeg),
                    globe.longitudeDeg.value_or(place.longitudeDeg),
                    globe.heightM.value_or(runtime::GlobeCameraPath::kOrbitHeightM)},
                   globe.headingDeg,
                   globe.pitchDeg},
                  runtime::GlobeCameraPath::kDefaultFovYDegrees}});
            if (!pose) return pose.error();
            Flight flown{runtime::FlightPath(std::move(pose).value()), {}, nullptr};
            if (globe.visit) flown.said = describeFlightPlan(plan.value(), durationS);
            return flown;
        }
        if (!pathFile.empty()) {
            auto loaded = runtime::FlightPath::load(pathFile, pathFrame());
            if (!loaded) return loaded.error();
            return Flight{std::move(loaded).value(), {}, nullptr};
        }
        auto plan = globeFlightPlan(pyramid, globe.visit);
        if (!plan) return plan.error();
        return Flight{runtime::FlightPath(globeTourFlight(plan.value(), durationS)),
                      describeFlightPlan(plan.value(), durationS),
                      flightPlanJson(plan.value(), durationS)};
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
    // The last frame's draw list by face level: data, virtual and bare patches, largest Err(P);
    // native tiles drawn whole ("data") and as windows below their samples ("window").
    nlohmann::json byLevel = nlohmann::json::object();
    for (const runtime::PatchDraw& d : facts.lastDraws) {
        const bool native = io::isNativeTile(d.id);
        nlohmann::json& level =
            byLevel[native ? std::string("native") : std::to_string(io::globePatchOf(d.id).level)];
        if (level.is_null())
            level = {{"data", 0}, {"virtual", 0}, {"bare", 0}, {"max_error_m", 0.0}};
        const char* kind = d.layer < 0    ? "bare"
                           : !d.isVirtual ? "data"
                           : native       ? "window"
                                          : "virtual";
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
