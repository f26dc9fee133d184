// SurfaceKit: each surface's kit refuses the other surface's LOD methods in the session's words
// and the globe's flags on a plane by name, reads a camera path file as its own surface's path
// (refusing the other format), takes frames every 1 / fps on the plane and over the whole path
// on the globe, and draws with its own sky and fog. No GL.
#include "SurfaceKit.h"

#include "TempFolder.h"

#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/GlobeCameraPath.h"
#include "terrain/runtime/PlaneSurface.h"

#include <gtest/gtest.h>
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace terrain::tools {
namespace {

io::PyramidManifest planarManifest() {
    auto layout = io::PyramidLayout::create(257, 129, 33, 8, 4);
    EXPECT_TRUE(layout) << layout.error().message;
    return io::PyramidManifest::forLayout(layout.value());
}

// The globe flags as a command line gives them (given() asks the app, which lives as long).
struct ParsedGlobeFlags {
    CLI::App app;
    GlobeFlags flags;
    explicit ParsedGlobeFlags(std::vector<std::string> args) {
        flags.addTo(app);
        args.insert(args.begin(), "program");
        std::vector<const char*> argv;
        for (const std::string& a : args) argv.push_back(a.c_str());
        app.parse(static_cast<int>(argv.size()), argv.data());
    }
};

TEST(SurfaceKit, OfTheManifestsSurface) {
    const auto plane = SurfaceKit::of(planarManifest());
    EXPECT_EQ(plane->kind(), runtime::SurfaceKind::Plane);
    EXPECT_EQ(plane->tiling(), "planar");
    EXPECT_EQ(plane->pathFrame(), runtime::PathFrame::Plane);
    const auto globe = SurfaceKit::of(runtime::SurfaceKind::Globe);
    EXPECT_EQ(globe->tiling(), "globe");
    EXPECT_EQ(globe->pathFrame(), runtime::PathFrame::Globe);
}

TEST(SurfaceKit, RefusesMethodsInTheSessionsWords) {
    const auto planeKit = SurfaceKit::of(runtime::SurfaceKind::Plane);
    const auto globeKit = SurfaceKit::of(runtime::SurfaceKind::Globe);
    const SurfaceKit& plane = *planeKit;
    const SurfaceKit& globe = *globeKit;
    for (const runtime::LodMethodInfo& info : runtime::lodMethods()) {
        EXPECT_TRUE(plane.supports("p.pyramid", info.method)) << info.name;
        EXPECT_EQ(bool(globe.supports("g.pyramid", info.method)), info.globe) << info.name;
    }
    const Status refused = globe.supports("g.pyramid", runtime::LodMethod::ChunkedLod);
    ASSERT_FALSE(refused);
    EXPECT_EQ(
        refused.error().message,
        "g.pyramid: a globe pyramid: " +
            runtime::lodMethodSupports(runtime::LodMethod::ChunkedLod, runtime::SurfaceKind::Globe)
                .error()
                .message);
    EXPECT_NE(refused.error().message.find("chunked-lod draws planar pyramids only; on a globe: "
                                           "yusov2011"),
              std::string::npos);
}

TEST(SurfaceKit, APlaneRefusesTheGlobesFlagsByName) {
    const auto planeKit = SurfaceKit::of(runtime::SurfaceKind::Plane);
    const auto globeKit = SurfaceKit::of(runtime::SurfaceKind::Globe);
    const SurfaceKit& plane = *planeKit;
    const SurfaceKit& globe = *globeKit;
    const ParsedGlobeFlags none({});
    EXPECT_TRUE(plane.refuseForeignFlags("p.pyramid", none.flags));
    const ParsedGlobeFlags parsedTwo({"--pitch", "-10", "--lat", "40"});
    const GlobeFlags& two = parsedTwo.flags;
    const Status refused = plane.refuseForeignFlags("p.pyramid", two);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().message,
              "p.pyramid: a planar pyramid; --lat, --pitch are for globe pyramids only");
    const ParsedGlobeFlags culling({"--no-horizon-culling"});
    EXPECT_EQ(plane.refuseForeignFlags("p.pyramid", culling.flags).error().message,
              "p.pyramid: a planar pyramid; --no-horizon-culling is for globe pyramids only");
    EXPECT_TRUE(globe.refuseForeignFlags("g.pyramid", two));
    EXPECT_TRUE(two.fixedPose());
    EXPECT_FALSE(ParsedGlobeFlags({"--heading", "30"}).flags.fixedPose());
}

TEST(SurfaceKit, ReadsAPathFileAsItsOwnSurfacesPath) {
    test::TempFolder temp;
    const io::PyramidManifest manifest = planarManifest();
    const runtime::PlaneSurface surface(manifest);
    const std::string planarFile = temp.file("planar.json");
    const std::string globeFile = temp.file("globe.json");
    ASSERT_TRUE(runtime::CameraPath::defaultFor(surface.geometry(), 6.0).save(planarFile));
    ASSERT_TRUE(runtime::GlobeCameraPath::fromOrbit(10.0, 20.0, 5.0, 8.0).save(globeFile));
    const auto planeKit = SurfaceKit::of(runtime::SurfaceKind::Plane);
    const auto globeKit = SurfaceKit::of(runtime::SurfaceKind::Globe);
    const SurfaceKit& plane = *planeKit;
    const SurfaceKit& globe = *globeKit;
    const GlobeFlags noFlags;

    auto planeDefault = plane.flight("p.pyramid", surface, "", 7.0, noFlags);
    ASSERT_TRUE(planeDefault) << planeDefault.error().message;
    EXPECT_EQ(planeDefault.value().path.frame(), runtime::PathFrame::Plane);
    EXPECT_EQ(planeDefault.value().path.durationS(), 7.0);
    auto planeFile = plane.flight("p.pyramid", surface, planarFile, 7.0, noFlags);
    ASSERT_TRUE(planeFile) << planeFile.error().message;
    EXPECT_EQ(planeFile.value().path.durationS(), 6.0);
    auto planeRefuses = plane.flight("p.pyramid", surface, globeFile, 7.0, noFlags);
    ASSERT_FALSE(planeRefuses);
    EXPECT_EQ(planeRefuses.error().message, runtime::CameraPath::load(globeFile).error().message);

    // The globe's flight from a file reads no surface; the plane's stands in.
    auto globeFromFile = globe.flight("g.pyramid", surface, globeFile, 7.0, noFlags);
    ASSERT_TRUE(globeFromFile) << globeFromFile.error().message;
    EXPECT_EQ(globeFromFile.value().path.frame(), runtime::PathFrame::Globe);
    // --visit picks a place of the default flight: a path file has none.
    const ParsedGlobeFlags visit({"--visit", "2"});
    auto visitAndPath = globe.flight("g.pyramid", surface, globeFile, 7.0, visit.flags);
    ASSERT_FALSE(visitAndPath);
    EXPECT_EQ(visitAndPath.error().message,
              "g.pyramid: --visit picks a place of the default flight; --path " + globeFile +
                  " gives a flight of its own");
    EXPECT_EQ(visit.flags.given(), std::vector<std::string>{"--visit"});
    EXPECT_FALSE(visit.flags.fixedPose());
    auto globeRefuses = globe.flight("g.pyramid", surface, planarFile, 7.0, noFlags);
    ASSERT_FALSE(globeRefuses);
    EXPECT_EQ(globeRefuses.error().message,
              runtime::GlobeCameraPath::load(planarFile).error().message);
}

TEST(SurfaceKit, FrameTimes) {
    const runtime::FlightPath path(runtime::GlobeCameraPath::fromOrbit(10.0, 20.0, 5.0, 8.0));
    const auto planeKit = SurfaceKit::of(runtime::SurfaceKind::Plane);
    const auto globeKit = SurfaceKit::of(runtime::SurfaceKind::Globe);
    const SurfaceKit& plane = *planeKit;
    const SurfaceKit& globe = *globeKit;
    EXPECT_EQ(plane.frameTimeS(path, 0, 5, 30.0), 0.0);
    EXPECT_EQ(plane.frameTimeS(path, 3, 5, 30.0), 3.0 / 30.0);
    EXPECT_EQ(plane.frameTimeS(path, 3, 100, 0.5), 6.0);
    EXPECT_EQ(globe.frameTimeS(path, 0, 5, 30.0), 0.0);
    EXPECT_EQ(globe.frameTimeS(path, 2, 5, 30.0), 4.0);
    EXPECT_EQ(globe.frameTimeS(path, 4, 5, 30.0), 8.0);
    EXPECT_EQ(globe.frameTimeS(path, 0, 1, 30.0), 0.0);
}

TEST(SurfaceKit, SkyFogAndTheLook) {
    const io::PyramidManifest manifest = planarManifest();
    const runtime::PlaneSurface surface(manifest);
    DrawStyleFlags look;
    look.wireframe = true;
    look.debugView = "level";
    runtime::TerrainStyle planeStyle, globeStyle;
    const auto plane = SurfaceKit::of(runtime::SurfaceKind::Plane);
    const auto globe = SurfaceKit::of(runtime::SurfaceKind::Globe);
    plane->applyLook(planeStyle, look, surface);
    globe->applyLook(globeStyle, look, surface);
    for (const runtime::TerrainStyle& s : {planeStyle, globeStyle}) {
        EXPECT_TRUE(s.wireframe);
        EXPECT_TRUE(s.skirts);
        EXPECT_EQ(s.debugView, runtime::TerrainDebugView::Level);
    }
    EXPECT_EQ(planeStyle.skyColor, runtime::TerrainStyle().skyColor);
    EXPECT_EQ(planeStyle.fogDensityPerM, look.fogDensityPerM(surface.geometry()));
    EXPECT_GT(planeStyle.fogDensityPerM, 0.0f);
    EXPECT_LT(globeStyle.skyColor[2], 0.1f);  // space
    EXPECT_EQ(globeStyle.fogDensityPerM, 0.0f);
    EXPECT_NE(plane->rootFaultMessage(), globe->rootFaultMessage());
}

TEST(SurfaceKit, ReportFieldsOfOneSurface) {
    FlightFacts facts;
    facts.pathFile = "flight.json";
    facts.fps = 12.0;
    facts.horizonCulled = 1;
    facts.visited = 4;
    const auto planeKit = SurfaceKit::of(runtime::SurfaceKind::Plane);
    const auto globeKit = SurfaceKit::of(runtime::SurfaceKind::Globe);
    nlohmann::json plane, globe;
    planeKit->addJsonFields(plane, facts);
    globeKit->addJsonFields(globe, facts);
    EXPECT_EQ(plane,
              (nlohmann::json{
                  {"path", "flight.json"}, {"fps", 12.0}, {"full_detail_after_arrival", nullptr}}));
    EXPECT_EQ(globe["path"], "flight.json");
    EXPECT_FALSE(globe.contains("fps"));
    EXPECT_EQ(globe["horizon_culled_fraction_of_visited"], 0.25);
    EXPECT_TRUE(globe["full_detail_after_arrival"].is_null());
    for (const char* key : {"end_pose", "last_frame_patches_by_level", "horizon_culling"})
        EXPECT_TRUE(globe.contains(key)) << key;
    facts.fixedPose = true;
    globeKit->addJsonFields(globe, facts);
    EXPECT_EQ(globe["path"], "fixed pose");
}

}  // namespace
}  // namespace terrain::tools
