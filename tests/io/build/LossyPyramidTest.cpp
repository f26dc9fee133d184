// Lossy storage (issue 19; Yusov & Shevtsov 2011, §4): terrain-build --max-error-m δ rounds
// level l's heights to whole multiples of 2δ_l, δ_l = δ · 2^(finest − l), and adds δ_l to
// Err(P). Every stored sample must lie within its patch's δ of the source, every source
// sample within Err(P) of every level's surface (both as terrain-inspect --verify --source
// checks them), Err_Appr must be the lossless pyramid's, and the pyramid smaller.
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/build/PyramidSourceCheck.h"

#include "FloatGeoTiff.h"
#include "TempFolder.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

using test::TempFolder;

constexpr int kWidth = 300;
constexpr int kHeight = 257;
constexpr double kNoData = -9999.0;
constexpr double kDelta = 0.5;

// Hills with heights of no round step (floats of 1/16384 m and finer), and a hole.
float hills(int x, int y) {
    if (std::hypot(x - 200, y - 60) < 11.0) return static_cast<float>(kNoData);
    return static_cast<float>(800.0 + 150.0 * std::sin(x / 13.0) * std::cos(y / 9.0) + 1.7 * x +
                              0.013 * y * y);
}

std::string writeTiff(const std::string& path, const std::vector<float>& samples, int epsg,
                      const std::array<double, 6>& geoTransform) {
    return test::writeFloatGeoTiff(path, geoTransform, kWidth, kHeight, samples, kNoData, epsg);
}

std::vector<float> hillSamples() {
    std::vector<float> samples;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) samples.push_back(hills(x, y));
    return samples;
}

std::string writeHills(const TempFolder& dir, const std::string& name,
                       const std::vector<float>& samples) {
    return writeTiff(dir.file(name), samples, 32610, {590000.0, 30.0, 0.0, 5220000.0, 0.0, -30.0});
}

std::unique_ptr<DemReader> open(const std::string& path) {
    auto reader = openDem({path});
    EXPECT_TRUE(reader) << reader.error().message;
    return reader ? std::move(reader).value() : nullptr;
}

PyramidBuildOptions smallPatches(double maxErrorM) {
    PyramidBuildOptions options;
    options.patchSamples = 33;
    options.blockQuads = 8;
    options.threads = 2;
    options.maxErrorM = maxErrorM;
    return options;
}

TEST(LossyPyramidTest, StoredSamplesStayWithinDeltaAndEveryBoundHolds) {
    TempFolder dir;
    const auto source = open(writeHills(dir, "hills.tif", hillSamples()));
    ASSERT_TRUE(source);
    const auto lossless = buildPyramid(*source, dir.path() / "lossless", smallPatches(0.0));
    ASSERT_TRUE(lossless) << lossless.error().message;
    const auto lossy = buildPyramid(*source, dir.path() / "lossy", smallPatches(kDelta));
    ASSERT_TRUE(lossy) << lossy.error().message;
    EXPECT_LT(lossy.value().bytes, lossless.value().bytes);

    const PyramidManifest& manifest = lossy.value().manifest;
    EXPECT_FALSE(lossless.value().manifest.quantization);
    ASSERT_TRUE(manifest.quantization);
    EXPECT_EQ(manifest.quantization->maxErrorM, kDelta);
    // The hills cross the edges of the steps: the largest difference is nearly δ.
    EXPECT_GT(manifest.quantization->finestLargestErrorM, 0.9 * kDelta);
    EXPECT_LE(manifest.quantization->finestLargestErrorM, kDelta + 1e-4);
    const int finest = manifest.layout.finestLevel();
    ASSERT_GE(finest, 3);

    // Patch by patch: Err_Appr is the exact heights' (the lossless pyramid's), δ at least
    // δ_l, Err(P) their sum, and the heights whole multiples of 2δ_l.
    auto lossyReader = PyramidReader::open(dir.path() / "lossy");
    auto losslessReader = PyramidReader::open(dir.path() / "lossless");
    ASSERT_TRUE(lossyReader && losslessReader);
    for (int level = 0; level <= finest; ++level) {
        const double halfStep = manifest.quantization->halfStep(level, finest);
        EXPECT_EQ(halfStep, kDelta * std::ldexp(1.0, finest - level));
        for (std::int64_t py = 0; py < manifest.layout.patchesY(level); ++py)
            for (std::int64_t px = 0; px < manifest.layout.patchesX(level); ++px) {
                const PatchId id{level, px, py};
                SCOPED_TRACE(::testing::Message()
                             << "L" << level << " (" << px << ", " << py << ")");
                auto stored = lossyReader.value().readPatch(id);
                auto exact = losslessReader.value().readPatch(id);
                ASSERT_TRUE(stored && exact);
                const PatchInfo& info = stored.value().info;
                EXPECT_EQ(info.approxError, exact.value().info.approxError);
                EXPECT_EQ(exact.value().info.quantError, 0.0f);
                EXPECT_GE(double(info.quantError), halfStep);
                EXPECT_LE(double(info.quantError), halfStep * (1.0 + 1e-6));
                EXPECT_GE(double(info.error), double(info.approxError) + double(info.quantError));
                int offGrid = 0;
                for (const float h : stored.value().heights) {
                    const double q = std::round(double(h) / (2.0 * halfStep));
                    offGrid += h == static_cast<float>(q * 2.0 * halfStep) ? 0 : 1;
                }
                EXPECT_EQ(offGrid, 0);
            }
    }

    // What terrain-inspect --verify --source checks: both bounds hold, at every level.
    const auto checked = checkErrorBoundsAgainstSource(dir.path() / "lossy", *source);
    ASSERT_TRUE(checked) << checked.error().message;
    EXPECT_EQ(checked.value().violationCount, 0);
    EXPECT_EQ(checked.value().storedViolationCount, 0);
    EXPECT_GT(checked.value().storedSamplesChecked, std::int64_t(kWidth) * kHeight);
    ASSERT_EQ(checked.value().largestStoredDifference.size(), manifest.levels.size());
    for (int level = 0; level <= finest; ++level) {
        const double difference =
            checked.value().largestStoredDifference[static_cast<std::size_t>(level)];
        const double halfStep = manifest.quantization->halfStep(level, finest);
        EXPECT_LE(difference, halfStep * (1.0 + 1e-6)) << level;
        EXPECT_GT(difference, 0.5 * halfStep) << level;  // the check sees the quantizer
    }
    // The lossless pyramid stores the source's samples exactly.
    const auto exact = checkErrorBoundsAgainstSource(dir.path() / "lossless", *source);
    ASSERT_TRUE(exact) << exact.error().message;
    EXPECT_EQ(exact.value().violationCount, 0);
    EXPECT_EQ(exact.value().storedViolationCount, 0);
    for (const double difference : exact.value().largestStoredDifference)
        EXPECT_EQ(difference, 0.0);
}

// The stored-sample check is not vacuous: a source sample moved by 3δ is found, named by
// its position, while the lossy pyramid itself is unchanged.
TEST(LossyPyramidTest, TheStoredSampleCheckFindsASampleBeyondDelta) {
    TempFolder dir;
    std::vector<float> samples = hillSamples();
    const auto source = open(writeHills(dir, "hills.tif", samples));
    ASSERT_TRUE(source);
    ASSERT_TRUE(buildPyramid(*source, dir.path() / "lossy", smallPatches(kDelta)));
    samples[static_cast<std::size_t>(40 * kWidth + 64)] += static_cast<float>(3.0 * kDelta);
    const auto moved = open(writeHills(dir, "moved.tif", samples));
    ASSERT_TRUE(moved);
    const auto checked = checkErrorBoundsAgainstSource(dir.path() / "lossy", *moved);
    ASSERT_TRUE(checked) << checked.error().message;
    // (64, 40) is on the grid of every level with a step dividing 8.
    EXPECT_GE(checked.value().storedViolationCount, 1);
    bool named = false;
    for (const ErrorBoundViolation& v : checked.value().violations)
        named = named || (v.stored && v.x == 64 && v.y == 40 && v.distanceM > 2.0 * kDelta);
    EXPECT_TRUE(named);
}

// A lossy pyramid whose manifest lost its quantizer is refused, not decoded with no step.
TEST(LossyPyramidTest, ShardsOfQuantizerStepsNeedTheManifestsQuantizer) {
    TempFolder dir;
    const auto source = open(writeHills(dir, "hills.tif", hillSamples()));
    ASSERT_TRUE(source);
    const auto built = buildPyramid(*source, dir.path() / "lossy", smallPatches(kDelta));
    ASSERT_TRUE(built) << built.error().message;
    PyramidManifest manifest = built.value().manifest;

    // The quantizer round-trips through the JSON; a bad one is refused, naming the field.
    const std::string json = toJson(manifest);
    auto read = fromJson(json, "manifest.json");
    ASSERT_TRUE(read) << read.error().message;
    EXPECT_EQ(read.value(), manifest);
    std::string otherRule = json;
    otherRule.replace(otherRule.find("\"yusov2011\""), 11, "\"constant\"");
    auto refused = fromJson(otherRule, "manifest.json");
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("quantization.rule"), std::string::npos);
    std::string zero = json;
    zero.replace(zero.find("\"maxErrorM\": 0.5"), 16, "\"maxErrorM\": 0.0");
    refused = fromJson(zero, "manifest.json");
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("quantization.maxErrorM"), std::string::npos);

    manifest.quantization.reset();
    ASSERT_TRUE(writeManifest(dir.path() / "lossy", manifest));
    auto reader = PyramidReader::open(dir.path() / "lossy");
    ASSERT_TRUE(reader) << reader.error().message;
    const auto patch = reader.value().readPatch({manifest.layout.finestLevel(), 0, 0});
    ASSERT_FALSE(patch);
    EXPECT_NE(patch.error().message.find("heightDivisor"), std::string::npos)
        << patch.error().message;
}

TEST(LossyPyramidTest, BadMaximumErrorsAreRefused) {
    TempFolder dir;
    const auto source = open(writeHills(dir, "hills.tif", hillSamples()));
    ASSERT_TRUE(source);
    const auto degrees = open(writeTiff(dir.file("degrees.tif"), hillSamples(), 4326,
                                        {-122.0, 0.001, 0.0, 47.0, 0.0, -0.001}));
    ASSERT_TRUE(degrees);
    for (const double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity()}) {
        const auto refused = buildPyramid(*source, dir.path() / "bad", smallPatches(bad));
        ASSERT_FALSE(refused) << bad;
        EXPECT_NE(refused.error().message.find("maximum storage error"), std::string::npos)
            << refused.error().message;
        EXPECT_FALSE(std::filesystem::exists(dir.path() / "bad"));
        const auto globe = buildGlobePyramid(*degrees, dir.path() / "globe", smallPatches(bad));
        ASSERT_FALSE(globe) << bad;
        EXPECT_NE(globe.error().message.find("maximum storage error"), std::string::npos)
            << globe.error().message;
        EXPECT_FALSE(std::filesystem::exists(dir.path() / "globe"));
    }
}

}  // namespace
}  // namespace terrain::io
