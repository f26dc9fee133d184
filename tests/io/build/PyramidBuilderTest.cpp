// The pyramid builder against its promises: lossless round trip, the error bound Err(P)
// holds for every full-resolution sample under every patch at every level (checked with
// a brute-force model of the renderer's triangulation), stored block errors are the
// block errors of the stored heights, bounds nest, and a failed or interrupted build
// leaves nothing that looks like a pyramid.
#include "terrain/build/NoDataFill.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/pyramid/ParentTileCache.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/source/DemReader.h"

#include "SharedData.h"
#include "TempFolder.h"
#include "TriangulationOracle.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;

using test::TempFolder;

// The whole DEM as the builder sees it: NaN for no-data.
std::vector<float> readAll(DemReader& reader) {
    const DemInfo& info = reader.info();
    std::vector<float> all(static_cast<std::size_t>(info.width * info.height));
    EXPECT_TRUE(reader.readWindow(0, 0, info.width, info.height, all).ok());
    return all;
}

struct Built {
    std::unique_ptr<DemReader> reader;
    std::vector<float> truth;  // NaN = no-data
    PyramidBuildSummary summary;
};

Built build(const std::vector<std::string>& inputs, const fs::path& out,
            const DemOpenOptions& open = {}, PyramidBuildOptions options = {}) {
    Built b;
    auto reader = openDem(inputs, open);
    EXPECT_TRUE(reader.ok()) << (reader.ok() ? "" : reader.error().message);
    b.reader = std::move(reader).value();
    b.truth = readAll(*b.reader);
    options.threads = 2;
    auto summary = buildPyramid(*b.reader, out, options);
    EXPECT_TRUE(summary.ok()) << (summary.ok() ? "" : summary.error().message);
    if (summary.ok()) b.summary = std::move(summary).value();
    return b;
}

// Every valid DEM sample under the patch lies within Err(P) of the patch's surface,
// whichever diagonal the tessellator draws. Returns the largest distance / Err(P) seen.
double checkErrorBound(const Built& b, const PyramidLayout& layout, const PatchRecord& patch) {
    const std::int64_t w = b.reader->info().width, h = b.reader->info().height;
    const std::int64_t s = layout.levelStep(patch.id.level);
    const int q = layout.patchQuads(), t = layout.tileSamples();
    const std::int64_t x0 = patch.id.x * q * s, y0 = patch.id.y * q * s;
    auto height = [&](int i, int j) { return double(patch.heights[(j + 1) * t + i + 1]); };
    double worst = 0.0;
    const double bound = double(patch.info.error);
    for (std::int64_t y = y0; y <= std::min(y0 + q * s, h - 1); ++y) {
        for (std::int64_t x = x0; x <= std::min(x0 + q * s, w - 1); ++x) {
            const float truth = b.truth[static_cast<std::size_t>(y * w + x)];
            if (std::isnan(truth)) continue;
            const double u = double(x - x0) / double(s), v = double(y - y0) / double(s);
            const int cx = std::min(int(u), q - 1), cy = std::min(int(v), q - 1);
            for (double z : test::cellSurfaceHeights(height, cx, cy, 1, u, v)) {
                const double distance = std::abs(z - truth);
                EXPECT_LE(distance, bound + 1e-4)
                    << "patch L" << patch.id.level << " (" << patch.id.x << ", " << patch.id.y
                    << ") sample (" << x << ", " << y << ")";
                if (bound > 0.0) worst = std::max(worst, distance / bound);
            }
        }
    }
    return worst;
}

// Checks every patch of small levels and a random sample of large ones.
void checkPyramid(const Built& b, const fs::path& out, int patchesPerLevel) {
    auto reader = PyramidReader::open(out);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    const PyramidLayout layout = reader.value().layout();
    std::mt19937 rng(7);
    double tightest = 0.0;
    for (int level = 0; level < layout.levelCount(); ++level) {
        const std::int64_t total = layout.patchesX(level) * layout.patchesY(level);
        for (int k = 0; k < std::min<std::int64_t>(patchesPerLevel, total); ++k) {
            const std::int64_t index = total <= patchesPerLevel ? k : std::int64_t(rng() % total);
            const PatchId id{level, index % layout.patchesX(level), index / layout.patchesX(level)};
            auto patch = reader.value().readPatch(id);
            ASSERT_TRUE(patch.ok()) << patch.error().message;
            const PatchRecord& p = patch.value();
            tightest = std::max(tightest, checkErrorBound(b, layout, p));

            // Stored λ(d) are the block errors of the stored heights (Yusov §5), rounded
            // up to halves.
            const int n = layout.patchSamples(), t = layout.tileSamples();
            std::vector<BlockErrors> expected(p.blockErrors.size());
            patchBlockErrors(GridView{p.heights.data() + t + 1, n, t}, layout.blockQuads(),
                             expected);
            for (BlockErrors& e : expected)
                for (float& lambda : e) lambda = roundUpToHalf(lambda);
            EXPECT_EQ(p.blockErrors, expected);
            EXPECT_GE(p.info.error, p.info.approxError);
            if (level == layout.finestLevel()) {
                EXPECT_EQ(p.info.error, 0.0f);
            }

            // Bounds nest: a parent's bound covers each child's.
            if (level < layout.finestLevel()) {
                for (int c = 0; c < 4; ++c) {
                    const PatchId child{level + 1, 2 * id.x + c % 2, 2 * id.y + c / 2};
                    if (!layout.contains(child)) continue;
                    auto info = reader.value().patchInfo(child);
                    ASSERT_TRUE(info.ok());
                    EXPECT_GE(p.info.approxError, info.value().approxError);
                }
            }
        }
    }
    // The bound is not vacuous: somewhere a sample comes close to it.
    EXPECT_GT(tightest, 0.5) << "Err(P) is never approached: the bound is suspiciously loose";
}

// Finest-level patches store the DEM's samples exactly (no-data: the documented fill).
void checkRoundTrip(const Built& b, const fs::path& out) {
    auto reader = PyramidReader::open(out);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    const PyramidLayout layout = reader.value().layout();
    const std::int64_t w = b.reader->info().width, h = b.reader->info().height;
    std::vector<float> filled = b.truth;
    std::vector<std::uint8_t> valid(filled.size());
    fillNoData(w, h, filled, valid, wholeSourceUnits(b.reader->info()));
    const int level = layout.finestLevel(), q = layout.patchQuads(), t = layout.tileSamples();
    std::int64_t compared = 0;
    for (std::int64_t py = 0; py < layout.patchesY(level); ++py) {
        for (std::int64_t px = 0; px < layout.patchesX(level); ++px) {
            auto patch = reader.value().readPatch({level, px, py});
            ASSERT_TRUE(patch.ok()) << patch.error().message;
            for (int j = 0; j < t; ++j) {
                for (int i = 0; i < t; ++i) {
                    // Apron and overhang take the nearest DEM sample.
                    const std::int64_t x = std::clamp<std::int64_t>(px * q - 1 + i, 0, w - 1);
                    const std::int64_t y = std::clamp<std::int64_t>(py * q - 1 + j, 0, h - 1);
                    ASSERT_EQ(patch.value().heights[j * t + i], filled[y * w + x])
                        << "patch (" << px << ", " << py << ") tile sample (" << i << ", " << j
                        << ")";
                    ++compared;
                }
            }
        }
    }
    EXPECT_GE(compared, w * h);
}

TEST(PyramidBuilder, ProceduralRoundTripAndErrorBounds) {
    TempFolder tmp;
    const fs::path out = tmp.path() / "procedural.pyramid";
    const Built b = build({"procedural:size=1025,seed=3"}, out);
    EXPECT_EQ(b.summary.manifest.layout.finestLevel(), 3);
    checkRoundTrip(b, out);
    checkPyramid(b, out, 1000);
}

// Below the root, patches are coded from their parents' samples (docs/pyramid-format.md,
// "Height codes"): a reader decodes a patch's ancestors first, keeps them for their other
// children, and names the parent when it is what cannot be read.
TEST(PyramidBuilder, FinerLevelsArePredictedFromTheirParents) {
    TempFolder tmp;
    const fs::path out = tmp.path() / "procedural.pyramid";
    const Built b = build({"procedural:size=1025,seed=3"}, out);
    ASSERT_EQ(b.summary.manifest.layout.finestLevel(), 3);
    {
        auto reader = PyramidReader::open(out);
        ASSERT_TRUE(reader.ok()) << reader.error().message;
        ASSERT_TRUE(reader.value().readPatch({3, 5, 2}).ok());
        EXPECT_EQ(reader.value().parentReads(), 3U);  // levels 2, 1 and 0
        for (const PatchId sibling : {PatchId{3, 4, 2}, PatchId{3, 4, 3}, PatchId{3, 5, 3}})
            ASSERT_TRUE(reader.value().readPatch(sibling).ok());
        EXPECT_EQ(reader.value().parentReads(), 3U);  // their parent was kept
    }
    {
        // Readers sharing one cache (an IoThread's reader threads) keep each other's parents;
        // a reader with a cache of its own reads them again.
        const auto shared = std::make_shared<ParentTileCache>(PyramidReader::kParentCacheBytes);
        auto first = PyramidReader::open(out, PyramidReader::kDefaultOpenShards, shared);
        auto second = PyramidReader::open(out, PyramidReader::kDefaultOpenShards, shared);
        auto alone = PyramidReader::open(out);
        ASSERT_TRUE(first.ok() && second.ok() && alone.ok());
        ASSERT_TRUE(first.value().readPatch({3, 5, 2}).ok());
        EXPECT_EQ(first.value().parentReads(), 3U);
        ASSERT_TRUE(second.value().readPatch({3, 4, 2}).ok());
        EXPECT_EQ(second.value().parentReads(), 0U);  // the first reader's parents
        ASSERT_TRUE(alone.value().readPatch({3, 4, 2}).ok());
        EXPECT_EQ(alone.value().parentReads(), 3U);
    }
    {
        // A cache smaller than a tile keeps the last parent decoded only: the level-2 parent
        // serves its other children, and a patch elsewhere reads its three ancestors again.
        auto reader = PyramidReader::open(out, PyramidReader::kDefaultOpenShards,
                                          std::make_shared<ParentTileCache>(1));
        ASSERT_TRUE(reader.ok());
        ASSERT_TRUE(reader.value().readPatch({3, 5, 2}).ok());
        ASSERT_TRUE(reader.value().readPatch({3, 4, 3}).ok());
        EXPECT_EQ(reader.value().parentReads(), 3U);
        ASSERT_TRUE(reader.value().readPatch({3, 0, 0}).ok());
        EXPECT_EQ(reader.value().parentReads(), 6U);
    }
    // The parent's shard gone: the child cannot be decoded, and the error says why.
    const PyramidLayout layout = b.summary.manifest.layout;
    const fs::path parentShard = out / layout.shardPath(layout.shardOf({2, 2, 1}));
    fs::remove(parentShard);
    auto reader = PyramidReader::open(out);
    ASSERT_TRUE(reader.ok());
    const auto child = reader.value().readPatch({3, 5, 2});
    ASSERT_FALSE(child.ok());
    const std::string& message = child.error().message;
    EXPECT_NE(message.find("patch L3 (5, 2): its heights are predicted from its parent's, which "
                           "cannot be read"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find(parentShard.string() + ": patch L2 (2, 1): the shard file is missing"),
              std::string::npos)
        << message;
}

// --independent-patches: every patch decodes without its parent, the same heights, in more
// bytes.
TEST(PyramidBuilder, IndependentPatchesDecodeAlone) {
    TempFolder tmp;
    const fs::path predicted = tmp.path() / "predicted.pyramid";
    const fs::path independent = tmp.path() / "independent.pyramid";
    build({"procedural:size=1025,seed=3"}, predicted);
    PyramidBuildOptions options;
    options.parentPrediction = false;
    const Built b = build({"procedural:size=1025,seed=3"}, independent, {}, options);
    checkRoundTrip(b, independent);
    auto alone = PyramidReader::open(independent);
    auto withParents = PyramidReader::open(predicted);
    ASSERT_TRUE(alone.ok() && withParents.ok());
    const PyramidLayout& layout = alone.value().layout();
    for (int level = layout.finestLevel(); level >= 0; --level)
        for (std::int64_t y = 0; y < layout.patchesY(level); ++y)
            for (std::int64_t x = 0; x < layout.patchesX(level); ++x) {
                auto a = alone.value().readPatch({level, x, y});
                auto p = withParents.value().readPatch({level, x, y});
                ASSERT_TRUE(a.ok() && p.ok());
                ASSERT_EQ(a.value().heights, p.value().heights);
            }
    EXPECT_EQ(alone.value().parentReads(), 0U);
    EXPECT_GT(withParents.value().parentReads(), 0U);
    const auto bytes = [](const fs::path& folder) {
        std::uintmax_t total = 0;
        for (const auto& entry : fs::recursive_directory_iterator(folder))
            if (entry.is_regular_file()) total += entry.file_size();
        return total;
    };
    EXPECT_LT(bytes(predicted), bytes(independent));
}

TEST(PyramidBuilder, OddSizedProceduralWithSmallPatches) {
    TempFolder tmp;
    const fs::path out = tmp.path() / "odd.pyramid";
    PyramidBuildOptions options;
    options.patchSamples = 33;
    options.blockQuads = 8;
    options.shardPatches = 3;  // shards that do not divide the levels evenly
    const Built b = build({"procedural:width=301,height=170,seed=5"}, out, {}, options);
    checkRoundTrip(b, out);
    checkPyramid(b, out, 1000);
}

TEST(PyramidBuilder, RainierWithVoidsKeepsBoundsOnValidSamples) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "srtm3_n46w122_rainier.tif");
    TempFolder tmp;
    const fs::path out = tmp.path() / "rainier.pyramid";
    const Built b = build({path.string()}, out);
    EXPECT_TRUE(b.summary.manifest.noData.present);
    EXPECT_EQ(b.summary.manifest.noData.samples, 9033);
    EXPECT_EQ(b.summary.manifest.statistics.minHeight, 263.0);
    EXPECT_EQ(b.summary.manifest.statistics.maxHeight, 4371.0);
    checkRoundTrip(b, out);
    checkPyramid(b, out, 40);
}

TEST(PyramidBuilder, PugetSoundScaledPng) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "puget_sound_1k.png");
    TempFolder tmp;
    const fs::path out = tmp.path() / "puget.pyramid";
    DemOpenOptions open;
    open.verticalScale = 0.1;
    open.pixelSize = 160.0;
    const Built b = build({path.string()}, out, open);
    EXPECT_NEAR(b.summary.manifest.statistics.maxHeight, 4379.8, 1e-3);
    checkPyramid(b, out, 40);
}

// Bytes in the files under `folder`.
std::uintmax_t folderBytes(const fs::path& folder) {
    std::uintmax_t total = 0;
    for (const auto& entry : fs::recursive_directory_iterator(folder))
        if (entry.is_regular_file()) total += entry.file_size();
    return total;
}

// An 8-bit grey DEM without georeference (issue 52: its lossless pyramid was 1.07 × its
// DEFLATE COG): the procedural DEM scaled to 0 … 255, written as a PNG, against GDAL's
// DEFLATE COG of the same PNG as tools/bench/pyramid_build_bench.py makes it. Most of what
// the pyramid holds beyond the COG is its block errors λ, which a COG has no counterpart
// for; the bound guards the payloads' coding (each part its own zstd block, no matches
// under 7 bytes): 1.38 × before it, 1.31 × since.
TEST(PyramidBuilder, EightBitGreyDemStaysNearItsDeflateCog) {
    TempFolder tmp;
    auto procedural = openDem({"procedural:size=1025,seed=3"});
    ASSERT_TRUE(procedural.ok()) << procedural.error().message;
    const std::vector<float> heights = readAll(*procedural.value());
    const auto [low, high] = std::minmax_element(heights.begin(), heights.end());
    std::vector<std::uint8_t> grey(heights.size());
    for (std::size_t i = 0; i < heights.size(); ++i)
        grey[i] = static_cast<std::uint8_t>(
            std::lround(255.0 * (double(heights[i]) - *low) / (double(*high) - *low)));
    constexpr int kSide = 1025;
    ASSERT_EQ(grey.size(), std::size_t{kSide} * kSide);

    GDALAllRegister();
    GDALDriver* memory = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
    GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
    ASSERT_TRUE(memory != nullptr && png != nullptr && cog != nullptr);
    GDALDataset* raster = memory->Create("", kSide, kSide, 1, GDT_Byte, nullptr);
    ASSERT_NE(raster, nullptr);
    ASSERT_EQ(raster->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, kSide, kSide, grey.data(), kSide,
                                                 kSide, GDT_Byte, 0, 0, nullptr),
              CE_None);
    const std::string pngPath = (tmp.path() / "grey.png").string();
    const std::string cogPath = (tmp.path() / "grey.cog.tif").string();
    GDALDataset* written =
        png->CreateCopy(pngPath.c_str(), raster, FALSE, nullptr, nullptr, nullptr);
    ASSERT_NE(written, nullptr);
    GDALClose(written);
    const char* cogOptions[] = {"COMPRESS=DEFLATE", "PREDICTOR=YES", nullptr};
    written = cog->CreateCopy(cogPath.c_str(), raster, FALSE, const_cast<char**>(cogOptions),
                              nullptr, nullptr);
    ASSERT_NE(written, nullptr);
    GDALClose(written);
    GDALClose(raster);

    const fs::path out = tmp.path() / "grey.pyramid";
    const Built b = build({pngPath}, out);
    checkRoundTrip(b, out);
    const double ratio = double(folderBytes(out)) / double(fs::file_size(cogPath));
    RecordProperty("pyramidToCog", std::to_string(ratio));
    EXPECT_LT(ratio, 1.33) << folderBytes(out) << " bytes against the COG's "
                           << fs::file_size(cogPath);
}

TEST(PyramidBuilder, InterruptedBuildLeavesNothing) {
    TempFolder tmp;
    const fs::path out = tmp.path() / "interrupted.pyramid";
    auto reader = openDem({"procedural:size=1025"});
    ASSERT_TRUE(reader.ok());
    std::atomic<bool> cancel{false};
    PyramidBuildOptions options;
    options.cancel = &cancel;
    options.progress = [&](const PyramidBuildProgress&) { cancel = true; };
    auto result = buildPyramid(*reader.value(), out, options);
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("interrupted"), std::string::npos);
    EXPECT_TRUE(fs::is_empty(tmp.path())) << "a partial folder was left behind";
}

TEST(PyramidBuilder, ExistingOutputNeedsOverwrite) {
    TempFolder tmp;
    const fs::path out = tmp.path() / "twice.pyramid";
    auto reader = openDem({"procedural:size=129"});
    ASSERT_TRUE(reader.ok());
    ASSERT_TRUE(buildPyramid(*reader.value(), out).ok());
    auto again = buildPyramid(*reader.value(), out);
    ASSERT_FALSE(again.ok());
    EXPECT_NE(again.error().message.find(out.string()), std::string::npos);
    EXPECT_NE(again.error().message.find("already exists"), std::string::npos);
    PyramidBuildOptions options;
    options.overwrite = true;
    EXPECT_TRUE(buildPyramid(*reader.value(), out, options).ok());
    EXPECT_TRUE(PyramidReader::open(out).ok());
}

TEST(PyramidBuilder, UnwritableOutputIsAClearError) {
    TempFolder tmp;
    const fs::path file = tmp.path() / "a-file";
    {
        std::FILE* f = std::fopen(file.c_str(), "w");
        std::fclose(f);
    }
    auto reader = openDem({"procedural:size=129"});
    ASSERT_TRUE(reader.ok());
    auto result = buildPyramid(*reader.value(), file / "pyramid");
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("a-file"), std::string::npos) << result.error().message;
}

// A float DEM whose samples left of column `validFrom` are NaN (no-data).
class PartlyEmptyDem final : public DemReader {
public:
    PartlyEmptyDem(std::int64_t width, std::int64_t height, std::int64_t validFrom)
        : m_validFrom(validFrom) {
        m_info.path = "partly-empty";
        m_info.readerName = "test";
        m_info.inputs = {"partly-empty"};
        m_info.width = width;
        m_info.height = height;
        m_info.sampleType = "float32";
    }
    const DemInfo& info() const override { return m_info; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        for (std::int64_t r = 0; r < rows; ++r)
            for (std::int64_t c = 0; c < width; ++c)
                out[static_cast<std::size_t>(r * width + c)] =
                    x0 + c < m_validFrom ? std::numeric_limits<float>::quiet_NaN()
                                         : static_cast<float>(100 + (x0 + c) % 7 + (y0 + r) % 5);
        return {};
    }

private:
    DemInfo m_info;
    std::int64_t m_validFrom;
};

// A raster without a valid sample would build a pyramid of nothing: refused, and nothing
// left behind. One mostly of no-data builds, with a warning naming the share.
TEST(PyramidBuilder, NoValidSampleIsRefusedAndMostlyNoDataIsWarnedAbout) {
    TempFolder tmp;
    PartlyEmptyDem empty(100, 80, 100);
    const auto refused = buildPyramid(empty, tmp.path() / "empty");
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("no valid sample"), std::string::npos)
        << refused.error().message;
    EXPECT_TRUE(refused.error().message.starts_with("partly-empty")) << refused.error().message;
    EXPECT_TRUE(fs::is_empty(tmp.path()));

    PartlyEmptyDem mostly(100, 80, 70);  // 70 % no-data
    const auto warned = buildPyramid(mostly, tmp.path() / "mostly");
    ASSERT_TRUE(warned.ok()) << warned.error().message;
    ASSERT_EQ(warned.value().warnings.size(), 1u);
    EXPECT_NE(warned.value().warnings.front().find("70.0 % of its 8000 samples are no-data"),
              std::string::npos)
        << warned.value().warnings.front();

    PartlyEmptyDem some(100, 80, 30);  // 30 %: no warning
    const auto quiet = buildPyramid(some, tmp.path() / "some");
    ASSERT_TRUE(quiet.ok()) << quiet.error().message;
    EXPECT_TRUE(quiet.value().warnings.empty());
}

}  // namespace
}  // namespace terrain::io
