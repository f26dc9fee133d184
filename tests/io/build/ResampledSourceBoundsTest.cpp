// A rotated or sheared DEM (issue 21) is built from GDAL's bilinear resampling of it, but its
// error bounds are the source's: every sample the user gave lies within Err(P) of every
// level's surface where it lies (terrain-inspect --verify --source), holes included; and
// the same check run against a pyramid of the resampled grid alone, whose bounds know
// nothing of the source, finds the samples it misses. On a globe the same holds.
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/build/PyramidSourceCheck.h"

#include "FloatGeoTiff.h"
#include "TempFolder.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

using test::TempFolder;

constexpr int kWidth = 150;
constexpr int kHeight = 120;
constexpr double kNoData = -9999.0;

// Hills steep enough that bilinear resampling misses the samples by decimetres, with a
// hole of no-data.
float height(int x, int y) {
    if (std::hypot(x - 100, y - 40) < 9.0) return static_cast<float>(kNoData);
    return static_cast<float>(400.0 + 120.0 * std::sin(x / 9.0) * std::cos(y / 7.0) + 2.0 * x);
}

std::string writeTiff(const std::string& path, const std::array<double, 6>& geoTransform, int width,
                      int height, const std::vector<float>& samples, std::optional<double> noData,
                      int epsg = 32610) {
    return test::writeFloatGeoTiff(path, geoTransform, width, height, samples, noData, epsg);
}

std::unique_ptr<DemReader> open(const std::string& path) {
    auto reader = openDem({path});
    EXPECT_TRUE(reader) << reader.error().message;
    return reader ? std::move(reader).value() : nullptr;
}

class ResampledSourceBoundsTest : public ::testing::TestWithParam<std::array<double, 6>> {
protected:
    PyramidBuildOptions smallPatches() const {
        PyramidBuildOptions options;
        options.patchSamples = 33;
        options.blockQuads = 8;
        options.threads = 2;
        return options;
    }
    TempFolder m_dir;
};

TEST_P(ResampledSourceBoundsTest, EveryLevelBoundsTheSourcesOwnSamples) {
    std::vector<float> samples;
    std::int64_t valid = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            samples.push_back(height(x, y));
            valid += samples.back() == float(kNoData) ? 0 : 1;
        }
    const std::string tiff =
        writeTiff(m_dir.file("tilted.tif"), GetParam(), kWidth, kHeight, samples, kNoData);
    const auto source = open(tiff);
    ASSERT_TRUE(source);
    ASSERT_TRUE(source->info().resampledFrom);

    const auto built = buildPyramid(*source, m_dir.path() / "tilted.pyramid", smallPatches());
    ASSERT_TRUE(built) << built.error().message;
    const PyramidManifest& manifest = built.value().manifest;
    ASSERT_GE(manifest.levels.size(), 3U);
    ASSERT_TRUE(manifest.source.resampled);
    EXPECT_EQ(manifest.source.resampled->validSamples, valid);
    EXPECT_EQ(manifest.source.resampled->geoTransform, GetParam());
    EXPECT_TRUE(manifest.noData.present);         // the grid's corners outside the source
    EXPECT_TRUE(built.value().warnings.empty());  // the source is mostly valid
    // Resampling costs something on these hills (most at the hole, whose rim cells are
    // filled), and the finest bounds say exactly that much.
    const double finestDistance = manifest.source.resampled->finestDistanceM;
    EXPECT_GT(finestDistance, 0.01);
    EXPECT_GE(manifest.levels.back().maxError, finestDistance);
    EXPECT_LT(manifest.levels.back().maxError, finestDistance * (1.0 + 1e-6));

    const auto checked = checkErrorBoundsAgainstSource(m_dir.path() / "tilted.pyramid", *source);
    ASSERT_TRUE(checked) << checked.error().message;
    EXPECT_EQ(checked.value().violationCount, 0);
    EXPECT_EQ(checked.value().samplesChecked, valid * std::int64_t(manifest.levels.size()));
    ASSERT_EQ(checked.value().tightestRatio.size(), manifest.levels.size());
    EXPECT_NEAR(checked.value().tightestRatio.back(), 1.0, 1e-6);  // tight at the finest

    // The resampled grid built as a north-up DEM of its own: bounds against it alone.
    const DemInfo& info = source->info();
    std::vector<float> grid(static_cast<std::size_t>(info.width * info.height));
    ASSERT_TRUE(source->readWindow(0, 0, info.width, info.height, grid));
    const Georeference& geo = info.georeference;
    const std::string plain =
        writeTiff(m_dir.file("resampled.tif"),
                  {geo.originX, geo.pixelSizeX, 0.0, geo.originY, 0.0, -geo.pixelSizeY},
                  static_cast<int>(info.width), static_cast<int>(info.height), grid, std::nullopt);
    const auto resampledOnly = open(plain);
    ASSERT_TRUE(resampledOnly);
    ASSERT_FALSE(resampledOnly->info().resampledFrom);
    ASSERT_TRUE(buildPyramid(*resampledOnly, m_dir.path() / "plain.pyramid", smallPatches()));
    const auto missed = checkErrorBoundsAgainstSource(m_dir.path() / "plain.pyramid", *source);
    ASSERT_TRUE(missed) << missed.error().message;
    EXPECT_GT(missed.value().violationCount, 0);
}

// A rotated geographic grid on the globe (issue 20): resampled north-up in degrees (as it
// opens by default) or onto the globe's longitude/latitude grid (as terrain-build --globe
// opens it), its own samples are placed on that grid and every one of them is within Err(P)
// at every level.
TEST(ResampledSourceGlobeTest, IsBoundedAtItsOwnSamples) {
    TempFolder dir;
    constexpr int kSide = 64;
    std::vector<float> samples;
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x)
            samples.push_back(
                static_cast<float>(100.0 + 3.0 * x + 40.0 * std::sin(0.3 * y) * std::cos(0.2 * x)));
    const std::string tiff =
        writeTiff(dir.file("tilted-degrees.tif"), {-122.0, 0.001, 0.0005, 47.0, 0.0005, -0.001},
                  kSide, kSide, samples, std::nullopt, 4326);
    for (const bool geographicGrid : {false, true}) {
        SCOPED_TRACE(geographicGrid ? "onto the globe's grid" : "north-up in degrees");
        DemOpenOptions options;
        options.geographicGrid = geographicGrid;
        auto source = openDem({tiff}, options);
        ASSERT_TRUE(source) << source.error().message;
        ASSERT_TRUE(source.value()->info().resampledFrom);
        EXPECT_EQ(source.value()->info().resampledFrom->fromCrs.empty(), !geographicGrid);
        const std::filesystem::path out =
            dir.path() / (geographicGrid ? "globe-grid.pyramid" : "north-up.pyramid");
        PyramidBuildOptions build;
        build.patchSamples = 17;
        build.blockQuads = 4;
        build.threads = 2;
        const auto built = buildGlobePyramid(*source.value(), out, build);
        ASSERT_TRUE(built) << built.error().message;
        EXPECT_EQ(built.value().manifest.statistics.validSamples, kSide * kSide);
        const auto report = checkErrorBoundsAgainstSource(out, *source.value());
        ASSERT_TRUE(report) << report.error().message;
        EXPECT_EQ(report.value().violationCount, 0);
        EXPECT_EQ(
            report.value().samplesChecked,
            std::int64_t{kSide} * kSide * (built.value().manifest.globe->faceFinestLevel + 1));
        EXPECT_GT(report.value().tightestRatio.back(), 0.999);
    }
}

// 30° rotated; sheared (rows slanting east); rotated with rows running north.
INSTANTIATE_TEST_SUITE_P(
    Placements, ResampledSourceBoundsTest,
    ::testing::Values(std::array<double, 6>{500000.0, 8.660254037844387, 5.0, 5200000.0, 5.0,
                                            -8.660254037844387},
                      std::array<double, 6>{500000.0, 10.0, 4.0, 5200000.0, 0.0, -10.0},
                      std::array<double, 6>{500000.0, 9.0, -3.0, 5200000.0, 3.0, 9.0}));

}  // namespace
}  // namespace terrain::io
