// The relief check terrain-build runs on every source: real terrain (the procedural DEM,
// the real DEMs at their true spacing and units) passes; the same heights read with the
// wrong spacing or unit, which draw as a forest of needles, are warned with the flags
// that fix them.
#include "GeographicFunctionDem.h"
#include "SharedData.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemSlope.h"
#include "terrain/source/ProceduralTerrain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace terrain::io {
namespace {

// Heights held in memory with the georeference a test gives them.
class GridDem final : public DemReader {
public:
    GridDem(std::int64_t width, std::int64_t height, std::vector<float> heights)
        : m_heights(std::move(heights)) {
        m_info.path = "grid.tif";
        m_info.readerName = "test";
        m_info.width = width;
        m_info.height = height;
        m_info.sampleType = "float32";
        m_info.georeference.crsKind = CrsKind::Unknown;
    }
    void place(double spacing) {
        m_info.hasGeoreference = true;
        m_info.georeference.crsKind = CrsKind::Projected;
        m_info.georeference.pixelSizeX = m_info.georeference.pixelSizeY = spacing;
    }
    const DemInfo& info() const override { return m_info; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        for (std::int64_t y = 0; y < rows; ++y)
            for (std::int64_t x = 0; x < width; ++x)
                out[std::size_t(y * width + x)] =
                    m_heights[std::size_t((y0 + y) * m_info.width + x0 + x)];
        return {};
    }

private:
    DemInfo m_info;
    std::vector<float> m_heights;
};

// The held-out polar grid's shape: heights anywhere from 0 to 11 km from one sample to
// the next, a quarter of them no-data.
std::vector<float> needleHeights(std::int64_t width, std::int64_t height) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> metres(0.0f, 11000.0f);
    std::vector<float> h(std::size_t(width * height));
    for (std::size_t i = 0; i < h.size(); ++i)
        h[i] = i % 4 == 0 ? std::numeric_limits<float>::quiet_NaN() : metres(random);
    return h;
}

TEST(DemSlope, NeedlesAtOneMetreAreWarnedWithTheFlagsThatFixThem) {
    GridDem dem(3000, 700, needleHeights(3000, 700));
    auto slopes = sampleSlopes(dem);
    ASSERT_TRUE(slopes.ok()) << slopes.error().message;
    EXPECT_EQ(slopes.value().metresPerColumn, 1.0);
    EXPECT_GT(slopes.value().pairs, 50000U);  // 32 pairs of rows, 2048 columns, no-data skipped
    EXPECT_GT(slopes.value().medianSlope, 1000.0);
    const std::optional<std::string> warning = absurdReliefWarning(dem.info(), slopes.value());
    ASSERT_TRUE(warning);
    EXPECT_TRUE(warning->starts_with("grid.tif: ")) << *warning;
    for (const char* flag : {"--spacing", "--vertical-scale", "--epsg"})
        EXPECT_NE(warning->find(flag), std::string::npos) << flag << " in " << *warning;

    // The same heights 5 km apart are steep but real (median about 0.7): no warning.
    dem.place(5000.0);
    slopes = sampleSlopes(dem);
    ASSERT_TRUE(slopes.ok());
    EXPECT_EQ(slopes.value().metresPerRow, 5000.0);
    EXPECT_LT(slopes.value().medianSlope, 1.0);
    EXPECT_FALSE(absurdReliefWarning(dem.info(), slopes.value()));
}

TEST(DemSlope, ProceduralTerrainIsReal) {
    ProceduralTerrainParameters p;
    p.widthSamples = p.heightSamples = 1025;
    Result<ProceduralTerrain> terrain = ProceduralTerrain::create(p);
    ASSERT_TRUE(terrain.ok());
    std::vector<float> h(std::size_t(1025 * 1025));
    terrain.value().fillWindow(0, 0, 1025, 1025, h);
    GridDem dem(1025, 1025, std::move(h));
    dem.place(p.sampleSpacingM);
    auto slopes = sampleSlopes(dem);
    ASSERT_TRUE(slopes.ok());
    EXPECT_GT(slopes.value().medianSlope, 0.0);
    EXPECT_LT(slopes.value().medianSlope, 1.0);
    EXPECT_FALSE(absurdReliefWarning(dem.info(), slopes.value()));
}

TEST(DemSlope, NothingValidIsNothingToJudge) {
    GridDem dem(40, 30, std::vector<float>(1200, std::numeric_limits<float>::quiet_NaN()));
    auto slopes = sampleSlopes(dem);
    ASSERT_TRUE(slopes.ok());
    EXPECT_EQ(slopes.value().pairs, 0U);
    EXPECT_FALSE(absurdReliefWarning(dem.info(), slopes.value()));
    GridDem one(1, 1, {5.0f});
    ASSERT_TRUE(sampleSlopes(one).ok());
}

// Degrees are metres on the ground: a 3" grid at 60° N is 46 m east-west, 93 m north-south.
TEST(DemSlope, GeographicSpacingIsMetresOnTheGround) {
    const double step = 1.0 / 1200.0;
    test::GeographicFunctionDem dem(
        10.0, 60.5, 1201, 1201, step, step,
        [](double, double longitude) { return float(1000.0 * std::sin(longitude * 20.0)); });
    auto slopes = sampleSlopes(dem);
    ASSERT_TRUE(slopes.ok());
    EXPECT_NEAR(slopes.value().metresPerColumn, 92.77 * 0.5, 0.5);
    EXPECT_NEAR(slopes.value().metresPerRow, 92.77, 0.1);
    EXPECT_FALSE(absurdReliefWarning(dem.info(), slopes.value()));
}

// The real DEMs at their true spacing and units pass; Puget Sound read as metres 1 m
// apart (what the issue flew: 13 frames of 48 over ε) is warned.
TEST(DemSlopeRealData, RealDemsPassAndPugetSoundAtOneMetreIsWarned) {
    TERRAIN_SHARED_DATA_OR_SKIP(puget, "puget_sound_1k.png");
    auto raw = openDem({puget.string()});
    ASSERT_TRUE(raw.ok()) << raw.error().message;
    auto slopes = sampleSlopes(*raw.value());
    ASSERT_TRUE(slopes.ok());
    EXPECT_TRUE(absurdReliefWarning(raw.value()->info(), slopes.value()))
        << slopes.value().medianSlope;

    DemOpenOptions truth;
    truth.pixelSize = 160.0;
    truth.verticalScale = 0.1;
    auto placed = openDem({puget.string()}, truth);
    ASSERT_TRUE(placed.ok());
    slopes = sampleSlopes(*placed.value());
    ASSERT_TRUE(slopes.ok());
    EXPECT_FALSE(absurdReliefWarning(placed.value()->info(), slopes.value()))
        << slopes.value().medianSlope;

    for (const char* name : {"srtm3_n46w122_rainier.tif", "etopo20_global.nc",
                             "kilauea_utm5n_30m.nc", "srtm/N57E011.hgt"}) {
        SCOPED_TRACE(name);
        auto dem = openDem({(test::sharedDataDir() / name).string()});
        ASSERT_TRUE(dem.ok()) << dem.error().message;
        slopes = sampleSlopes(*dem.value());
        ASSERT_TRUE(slopes.ok()) << slopes.error().message;
        EXPECT_GT(slopes.value().pairs, 1000U);
        EXPECT_LT(slopes.value().medianSlope, 1.0);
        EXPECT_FALSE(absurdReliefWarning(dem.value()->info(), slopes.value()));
        EXPECT_TRUE(dem.value()->info().warnings.empty()) << dem.value()->info().warnings[0];
    }
}

}  // namespace
}  // namespace terrain::io
