// The procedural planet (ProceduralPlanet) and its geographic DEM ("planet:"): seamless at
// the antimeridian and the poles, read window by window to the same samples, at any size up
// to 2^21 + 1 × 2^20 + 1 samples and beyond.
#include "terrain/source/ProceduralDems.h"
#include "terrain/source/DemReader.h"
#include "terrain/source/ProceduralPlanet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace terrain::io {
namespace {

TEST(ProceduralPlanet, SeamlessAcrossTheAntimeridianAndAtThePoles) {
    const ProceduralPlanet planet = ProceduralPlanet::create({.seed = 9});
    for (double latitude = -89.0; latitude <= 89.0; latitude += 7.0)
        EXPECT_NEAR(planet.heightAtDegrees(latitude, 180.0),
                    planet.heightAtDegrees(latitude, -180.0), 1e-6);
    for (double longitude = -180.0; longitude < 180.0; longitude += 30.0) {
        EXPECT_NEAR(planet.heightAtDegrees(90.0, longitude), planet.heightAtDegrees(90.0, 0.0),
                    1e-6);
        EXPECT_NEAR(planet.heightAtDegrees(-90.0, longitude), planet.heightAtDegrees(-90.0, 0.0),
                    1e-6);
    }
    // Relief worth flying over: kilometres between the lowest and highest of a 1° grid, and
    // every height within the bound.
    double lowest = 1e9, highest = -1e9;
    for (int lat = -89; lat <= 89; ++lat) {
        for (int lon = -180; lon < 180; ++lon) {
            const double h = planet.heightAtDegrees(lat, lon);
            lowest = std::min(lowest, h);
            highest = std::max(highest, h);
        }
    }
    EXPECT_GT(highest - lowest, 6000.0);
    EXPECT_LE(std::max(-lowest, highest), planet.heightBound());
    // Seeds make other planets.
    EXPECT_NE(planet.heightAtDegrees(10.0, 20.0),
              ProceduralPlanet::create({.seed = 10}).heightAtDegrees(10.0, 20.0));
}

// lowPassed keeps the planet's waves longer than the footprint and lostRoughness tells what
// it took away: the variance of the planet about its low-passed self, measured, matches it.
TEST(ProceduralPlanet, LowPassedKeepsTheLongWavesAndCountsTheRest) {
    const ProceduralPlanet planet = ProceduralPlanet::create({.seed = 4});
    const ProceduralPlanet same = planet.lowPassed(0.0);
    EXPECT_EQ(same.heightAtDegrees(12.3, 45.6), planet.heightAtDegrees(12.3, 45.6));
    EXPECT_EQ(planet.lostRoughness(0.0, 6.371e6).heightVarianceM2, 0.0);

    // σ of 10 km on the ground: the continents stay, the mountains' fine octaves go.
    const double sigma = 1e4 / 6.371e6;
    const ProceduralPlanet smooth = planet.lowPassed(sigma);
    const ProceduralPlanet::Roughness lost = planet.lostRoughness(sigma, 6.371e6);
    double sumSquares = 0.0, sumPlanet = 0.0;
    int count = 0;
    for (int lat = -80; lat <= 80; lat += 2) {
        for (int lon = -180; lon < 180; lon += 2) {
            const double residual = planet.heightAtDegrees(lat + 0.37, lon + 0.61) -
                                    smooth.heightAtDegrees(lat + 0.37, lon + 0.61);
            sumSquares += residual * residual;
            sumPlanet += planet.heightAtDegrees(lat, lon) * planet.heightAtDegrees(lat, lon);
            ++count;
        }
    }
    const double measured = sumSquares / count;
    EXPECT_GT(lost.heightVarianceM2, 0.0);
    EXPECT_LT(lost.heightVarianceM2, 0.1 * sumPlanet / count);  // the continents stay
    // A Gaussian's response is not a box's: the residual's variance is the lost energy's
    // order, not equal to it.
    EXPECT_GT(measured, 0.3 * lost.heightVarianceM2);
    EXPECT_LT(measured, 3.0 * lost.heightVarianceM2);
    EXPECT_GT(lost.slopeVariance, 0.0);
    // A wider footprint loses more.
    const ProceduralPlanet::Roughness wider = planet.lostRoughness(4.0 * sigma, 6.371e6);
    EXPECT_GT(wider.heightVarianceM2, lost.heightVarianceM2);
    EXPECT_GT(wider.slopeVariance, lost.slopeVariance);
}

TEST(ProceduralPlanet, ReadsAsAGeographicDemWindowByWindow) {
    auto whole = openProceduralDem("planet:seed=9");
    ASSERT_TRUE(whole) << whole.error().message;
    const DemInfo& info = whole.value()->info();
    EXPECT_EQ(info.width, (std::int64_t{1} << 21) + 1);
    EXPECT_EQ(info.height, (std::int64_t{1} << 20) + 1);
    EXPECT_EQ(info.georeference.crsKind, CrsKind::Geographic);
    EXPECT_EQ(info.georeference.epsg, Georeference::kWgs84Geographic);

    // A window in the middle of the planet, and a window inside it: the same samples.
    const std::int64_t x0 = 1'500'000, y0 = 600'000;
    std::vector<float> big(64 * 48), small(10 * 7);
    ASSERT_TRUE(whole.value()->readWindow(x0, y0, 64, 48, big));
    ASSERT_TRUE(whole.value()->readWindow(x0 + 20, y0 + 30, 10, 7, small));
    for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 10; ++i)
            ASSERT_EQ(small[static_cast<std::size_t>(j * 10 + i)],
                      big[static_cast<std::size_t>((j + 30) * 64 + i + 20)]);
    // Sample (i, j) is the planet at longitude −180 + i·d, latitude 90 − j·d.
    const double d = 360.0 / double(info.width - 1);
    const ProceduralPlanet planet = ProceduralPlanet::create({.seed = 9});
    EXPECT_EQ(big[0], static_cast<float>(
                          planet.heightAtDegrees(90.0 - double(y0) * d, -180.0 + double(x0) * d)));

    // A box of it: samples d = 90° / (2^8 · 128) apart from its north-west corner, the east
    // and south edges rounded to that grid.
    auto box = openProceduralDem("planet:seed=9,level=8,west=10,south=45,east=11,north=46");
    ASSERT_TRUE(box) << box.error().message;
    EXPECT_EQ(box.value()->info().width, 365);
    EXPECT_EQ(box.value()->info().height, 365);
    std::vector<float> corner(1);
    ASSERT_TRUE(box.value()->readWindow(364, 364, 1, 1, corner));
    const double d8 = 90.0 / (256.0 * 128.0);
    EXPECT_EQ(corner[0],
              static_cast<float>(planet.heightAtDegrees(46.0 - 364.0 * d8, 10.0 + 364.0 * d8)));
}

TEST(ProceduralPlanet, RefusesBadSpecs) {
    for (const char* bad : {"planet:level=17", "planet:colour=blue", "planet:seed",
                            "planet:west=20,east=10", "planet:north=91", "planet:seed=-1"}) {
        auto refused = openProceduralDem(bad);
        ASSERT_FALSE(refused) << bad;
        EXPECT_NE(refused.error().message.find(bad), std::string::npos) << refused.error().message;
    }
}

}  // namespace
}  // namespace terrain::io
