// GlobeTour: the default globe flight visits every local source of a composite (issue 52: it
// visited the finest only), tiles that touch as one place, from the finest source on by the
// nearest next, flying over global grids; a pyramid of one source, or a manifest that records
// no source's extent, gives the place the flight always went to. No GL, no file.
#include "GlobeTour.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace terrain::tools {
namespace {

io::ManifestGlobeSource source(std::string input, double west, double south, double east,
                               double north) {
    return {std::move(input), west, south, east, north, {}};
}

// As a build writes it: sourceExtent is the finest (first) source's.
io::ManifestGlobe globeOf(std::vector<io::ManifestGlobeSource> sources) {
    io::ManifestGlobe g;
    if (!sources.empty()) {
        g.west = sources.front().west;
        g.south = sources.front().south;
        g.east = sources.front().east;
        g.north = sources.front().north;
    }
    g.sources = std::move(sources);
    return g;
}

std::vector<std::string> firstInputs(const GlobeTourPlan& plan) {
    std::vector<std::string> inputs;
    for (const GlobeTourPlace& place : plan.places) inputs.push_back(place.inputs.front());
    return inputs;
}

TEST(GlobeTour, VisitsEveryLocalSourceAndFliesOverTheGlobalGrid) {
    // The composite: Rainier (SRTM3), a Swedish SRTM tile and ETOPO's global grid,
    // finest first as the build keeps them.
    const GlobeTourPlan plan = planGlobeTour(globeOf({
        source("/d/N57E011.hgt", 10.99958, 56.99958, 12.00042, 58.00042),
        source("/d/srtm3_n46w122_rainier.tif", -122.0004, 45.9996, -120.9996, 47.0004),
        source("/d/etopo20_global.nc", -180.0, -90.0, 180.0, 90.0),
    }));
    EXPECT_TRUE(plan.perSource);
    ASSERT_EQ(plan.places.size(), 2u);
    EXPECT_EQ(firstInputs(plan),
              (std::vector<std::string>{"/d/N57E011.hgt", "/d/srtm3_n46w122_rainier.tif"}));
    EXPECT_EQ(plan.global, std::vector<std::string>{"/d/etopo20_global.nc"});
    EXPECT_NEAR(plan.places[0].latitudeDeg, 57.5, 1e-9);
    EXPECT_NEAR(plan.places[0].longitudeDeg, 11.5, 1e-9);
    EXPECT_NEAR(plan.places[1].latitudeDeg, 46.5, 1e-9);
    EXPECT_NEAR(plan.places[1].longitudeDeg, -121.5, 1e-9);
}

TEST(GlobeTour, OneSourceGoesWhereTheFlightAlwaysWent) {
    // The centre exactly as globeFlightTarget computed it from sourceExtent before.
    const double w = -122.0004, s = 45.9996, e = -120.9996, n = 47.0004;
    const GlobeTourPlan plan = planGlobeTour(globeOf({source("rainier.tif", w, s, e, n)}));
    ASSERT_EQ(plan.places.size(), 1u);
    EXPECT_EQ(plan.places[0].latitudeDeg, 0.5 * (s + n));
    EXPECT_EQ(plan.places[0].longitudeDeg, std::remainder(w + 0.5 * (e - w), 360.0));
    EXPECT_TRUE(plan.global.empty());
    // Across the antimeridian: the middle of the short span.
    const GlobeTourPlan strip =
        planGlobeTour(globeOf({source("fiji", 179.0, -18.0, -179.0, -16.0)}));
    EXPECT_NEAR(std::abs(strip.places[0].longitudeDeg), 180.0, 1e-9);
    // A manifest written before each source's extent was: its one extent.
    io::ManifestGlobe old = globeOf({source("rainier.tif", w, s, e, n)});
    old.sources.clear();
    const GlobeTourPlan before = planGlobeTour(old);
    EXPECT_FALSE(before.perSource);
    ASSERT_EQ(before.places.size(), 1u);
    EXPECT_EQ(before.places[0].latitudeDeg, plan.places[0].latitudeDeg);
    EXPECT_EQ(before.places[0].longitudeDeg, plan.places[0].longitudeDeg);
    EXPECT_TRUE(before.places[0].inputs.empty());
    // A global grid alone: its centre, as before.
    const GlobeTourPlan global = planGlobeTour(globeOf({source("etopo", -180, -90, 180, 90)}));
    ASSERT_EQ(global.places.size(), 1u);
    EXPECT_EQ(global.places[0].latitudeDeg, 0.0);
    EXPECT_EQ(global.places[0].longitudeDeg, 0.0);
    EXPECT_EQ(global.global, std::vector<std::string>{"etopo"});
}

TEST(GlobeTour, TouchingTilesAreOnePlace) {
    // Two SRTM tiles side by side (their edge rows overlap), a third above the second, and a
    // lone one far away: two places, the tiles' box centre the first.
    const GlobeTourPlan plan = planGlobeTour(globeOf({
        source("N46E010", 9.99958, 45.99958, 11.00042, 47.00042),
        source("far", 100.0, -10.0, 101.0, -9.0),
        source("N46E011", 10.99958, 45.99958, 12.00042, 47.00042),
        source("N47E011", 10.99958, 46.99958, 12.00042, 48.00042),
    }));
    ASSERT_EQ(plan.places.size(), 2u);
    EXPECT_EQ(plan.places[0].inputs, (std::vector<std::string>{"N46E010", "N46E011", "N47E011"}));
    EXPECT_NEAR(plan.places[0].west, 9.99958, 1e-9);
    EXPECT_NEAR(plan.places[0].east, 12.00042, 1e-9);
    EXPECT_NEAR(plan.places[0].north, 48.00042, 1e-9);
    // The L's box centre (11°, 47°) lies on the tiles: it is where the flight goes.
    EXPECT_NEAR(plan.places[0].latitudeDeg, 47.0, 1e-9);
    EXPECT_NEAR(plan.places[0].longitudeDeg, 11.0, 1e-9);
    EXPECT_EQ(plan.places[1].inputs, std::vector<std::string>{"far"});
    // An L whose box centre falls beside it: the finest tile's centre instead.
    const GlobeTourPlan l = planGlobeTour(globeOf({
        source("a", 0.0, 0.0, 1.0, 1.0),
        source("b", 1.0, 0.0, 2.0, 1.0),
        source("c", 2.0, 0.0, 3.0, 1.0),
        source("d", 2.0, 1.0, 3.0, 2.0),
        source("e", 2.0, 2.0, 3.0, 3.0),
    }));
    ASSERT_EQ(l.places.size(), 1u);
    EXPECT_NEAR(l.places[0].latitudeDeg, 0.5, 1e-9);
    EXPECT_NEAR(l.places[0].longitudeDeg, 0.5, 1e-9);
    // Tiles either side of the antimeridian touch there.
    const GlobeTourPlan across = planGlobeTour(globeOf({
        source("west", 179.0, 0.0, 180.0, 1.0),
        source("east", -180.0, 0.0, -179.0, 1.0),
    }));
    ASSERT_EQ(across.places.size(), 1u);
    EXPECT_NEAR(across.places[0].west, 179.0, 1e-9);
    EXPECT_NEAR(across.places[0].east, -179.0, 1e-9);
    EXPECT_NEAR(std::abs(across.places[0].longitudeDeg), 180.0, 1e-9);
}

TEST(GlobeTour, FromTheFinestByTheNearestNext) {
    const GlobeTourPlan plan = planGlobeTour(globeOf({
        source("finest", 0.0, 0.0, 1.0, 1.0),
        source("farthest", 100.0, 0.0, 101.0, 1.0),
        source("near", 10.0, 0.0, 11.0, 1.0),
        source("middle", 50.0, 0.0, 51.0, 1.0),
        source("world", -180.0, -80.0, 180.0, 80.0),
    }));
    EXPECT_EQ(firstInputs(plan),
              (std::vector<std::string>{"finest", "near", "middle", "farthest"}));
    EXPECT_EQ(plan.global, std::vector<std::string>{"world"});
}

TEST(GlobeTour, ShareOfTheEarth) {
    EXPECT_NEAR(extentShareOfEarth(-180, -90, 180, 90), 1.0, 1e-12);
    EXPECT_NEAR(extentShareOfEarth(-180, 0, 180, 90), 0.5, 1e-12);
    EXPECT_NEAR(extentShareOfEarth(0, -90, 180, 90), 0.5, 1e-12);
    EXPECT_NEAR(extentShareOfEarth(170, -90, -170, 90), 20.0 / 360.0, 1e-12);
    // An Arctic grid around every longitude north of 60° is a regional one: visited.
    EXPECT_LT(extentShareOfEarth(-180, 60, 180, 90), kGlobalShare);
    EXPECT_LT(extentShareOfEarth(10, 46, 11, 47), 1e-4);
}

}  // namespace
}  // namespace terrain::tools
