// The pyramid format on disk (docs/pyramid-format.md): manifest round trip and errors,
// shards written and read back bit for bit, absent and missing patches, damaged files
// (every flipped byte and every truncation of a small shard), failed writes, the reader's
// LRU of open shards, the payload bytes it counts.
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/pyramid/ShardWriter.h"

#include "TinyPyramid.h"

#include "TempFolder.h"

#include <ImfDeepFrameBuffer.h>
#include <ImfDeepTiledInputPart.h>
#include <ImfHeader.h>
#include <ImfMultiPartInputFile.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& needle) {
    return text.find(needle) != std::string::npos;
}

std::vector<char> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const std::vector<char>& bytes, std::size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(size));
}

void writeText(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
}

// Random heights with the float values a lossless format must keep: signed zero,
// subnormals, extremes, NaN payloads.
PatchRecord randomRecord(const PyramidLayout& layout, const PatchId& id, bool withMask,
                         std::mt19937& rng) {
    PatchRecord r;
    r.id = id;
    const auto tile2 = static_cast<std::size_t>(layout.tileSamples() * layout.tileSamples());
    std::uniform_real_distribution<float> height(-500.0f, 9000.0f);
    r.heights.resize(tile2);
    for (float& h : r.heights) h = height(rng);
    r.heights[0] = -0.0f;
    r.heights[1] = std::numeric_limits<float>::denorm_min();
    r.heights[2] = std::numeric_limits<float>::max();
    r.heights[3] = std::numeric_limits<float>::lowest();
    r.heights[4] = std::bit_cast<float>(0x7fc01234U);
    if (withMask) {
        r.valid.resize(tile2);
        for (auto& v : r.valid) v = static_cast<std::uint8_t>(rng() % 4 != 0);
    }
    const auto blocks = static_cast<std::size_t>(layout.blocksPerSide() * layout.blocksPerSide());
    std::uniform_real_distribution<float> error(0.0f, 50.0f);
    r.blockErrors.resize(blocks);
    for (auto& b : r.blockErrors)
        for (float& e : b) e = error(rng);
    r.info.present = true;
    r.info.minHeight = height(rng);
    r.info.maxHeight = r.info.minHeight + 10.0f;
    r.info.approxError = error(rng);
    r.info.quantError = 0.0f;
    r.info.error = r.info.approxError;
    r.info.noDataSamples = static_cast<std::uint32_t>(rng() % 100);
    r.info.crc32 = 0xDEADBEEF;  // ignored by the writer
    return r;
}

void expectSameRecord(const PatchRecord& expected, const PatchRecord& actual) {
    EXPECT_EQ(actual.id, expected.id);
    ASSERT_EQ(actual.heights.size(), expected.heights.size());
    EXPECT_EQ(std::memcmp(actual.heights.data(), expected.heights.data(),
                          expected.heights.size() * sizeof(float)),
              0)
        << "heights differ";
    EXPECT_EQ(actual.valid, expected.valid);
    ASSERT_EQ(actual.blockErrors.size(), expected.blockErrors.size());
    // Stored as the halves no smaller than them.
    std::vector<BlockErrors> stored = expected.blockErrors;
    for (BlockErrors& b : stored)
        for (float& lambda : b) lambda = roundUpToHalf(lambda);
    EXPECT_EQ(
        std::memcmp(actual.blockErrors.data(), stored.data(), stored.size() * sizeof(BlockErrors)),
        0)
        << "block errors differ";
    PatchInfo info = expected.info;
    info.crc32 = actual.info.crc32;  // the writer's
    EXPECT_EQ(actual.info, info);
}

class PyramidFormat : public ::testing::Test {
protected:
    // Writes one shard of `layout` with random patches (all but `absent`) and a manifest;
    // returns the records written by patch index within the shard.
    std::vector<PatchRecord> writeRandomShard(const PyramidLayout& layout, const ShardId& s,
                                              bool withMask, const std::vector<PatchId>& absent,
                                              std::uint32_t seed,
                                              const ShardWriterOptions& options = {}) {
        std::mt19937 rng(seed);
        std::vector<PatchRecord> records;
        for (int ty = 0; ty < layout.shardCountY(s); ++ty)
            for (int tx = 0; tx < layout.shardCountX(s); ++tx) {
                const PatchId id{s.level, layout.shardFirstX(s) + tx, layout.shardFirstY(s) + ty};
                if (std::find(absent.begin(), absent.end(), id) != absent.end()) continue;
                records.push_back(randomRecord(layout, id, withMask, rng));
            }
        std::vector<std::size_t> order(records.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::shuffle(order.begin(), order.end(), rng);  // any order is allowed
        auto writer =
            ShardWriter::create(m_dir / layout.shardPath(s), layout, s, withMask, options);
        EXPECT_TRUE(writer.ok()) << writer.error().message;
        for (std::size_t i : order) {
            const Status ok = writer.value().writePatch(records[i]);
            EXPECT_TRUE(ok.ok()) << ok.error().message;
        }
        const Status finished = writer.value().finish();
        EXPECT_TRUE(finished.ok()) << finished.error().message;
        PyramidManifest manifest = PyramidManifest::forLayout(layout);
        manifest.noData.present = withMask;
        const Status written = writeManifest(m_dir, manifest);
        EXPECT_TRUE(written.ok()) << written.error().message;
        return records;
    }

    test::TempFolder m_tmp;
    fs::path m_dir = m_tmp.path();
};

// ---------------------------------------------------------------------------------------
// Manifest

PyramidManifest sampleManifest() {
    PyramidManifest m = PyramidManifest::forLayout(PyramidLayout::create(1201, 1201).value());
    m.georeference.crsKind = CrsKind::Geographic;
    m.georeference.epsg = 4326;
    m.georeference.wkt = "GEOGCS[\"WGS 84\"]";
    m.georeference.originX = -122.000416666666666;
    m.georeference.originY = 47.000416666666666;
    m.georeference.pixelSizeX = 1.0 / 1200.0;
    m.georeference.pixelSizeY = 1.0 / 1200.0;
    m.vertical = {0.1, -20.5};
    m.noData = {true, -32768.0, 9033, "membrane", {{"rainier.tif", -32768.0, true, 9033, 0}}};
    m.statistics = {263.0, 4371.25, 1433368, 1450.2000732421875};
    for (ManifestLevel& l : m.levels) l.maxError = 1.0 / 3.0 + l.level;
    m.levels[4].presentPatches = 97;
    m.source = {{"srtm3_n46w122_rainier.tif", "b.tif"}, "oiio", "int16"};
    m.build = {"terrain-build", "0.1.0", 1.25};
    return m;
}

TEST_F(PyramidFormat, ManifestRoundTrip) {
    const PyramidManifest m = sampleManifest();
    const auto back = fromJson(toJson(m), "test");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back.value(), m);

    PyramidManifest plain =
        PyramidManifest::forLayout(PyramidLayout::create(2, 2, 5, 4, 1).value());
    plain.noData.sourceValue.reset();  // written as null
    plain.georeference.epsg = 0;       // written as null
    plain.georeference.crsKind = CrsKind::Unknown;
    const auto plainBack = fromJson(toJson(plain), "test");
    ASSERT_TRUE(plainBack.ok()) << plainBack.error().message;
    EXPECT_EQ(plainBack.value(), plain);
    // Nothing filled: the manifest versions before the void fill wrote, no per-source list.
    const auto plainJson = nlohmann::json::parse(toJson(plain));
    EXPECT_EQ(plainJson["noData"]["fill"], "row-linear");
    EXPECT_FALSE(plainJson["noData"].contains("sources"));

    ASSERT_TRUE(writeManifest(m_dir, m).ok());
    const auto read = readManifest(m_dir);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read.value(), m);
    // Written through an AtomicFile: nothing but the manifest is left in the folder.
    EXPECT_EQ(std::distance(fs::directory_iterator(m_dir), fs::directory_iterator()), 1);
}

TEST_F(PyramidFormat, ManifestJsonHasTheSpecsKeys) {
    const auto json = nlohmann::json::parse(toJson(sampleManifest()));
    EXPECT_EQ(json["format"], "terrain-pyramid");
    EXPECT_EQ(json["formatVersion"], 8);
    EXPECT_EQ(json["raster"]["width"], 1201);
    EXPECT_EQ(json["georeference"]["crsKind"], "geographic");
    EXPECT_EQ(json["georeference"]["epsg"], 4326);
    EXPECT_EQ(json["georeference"]["verticalUnits"], "metre");
    EXPECT_EQ(json["noData"]["fill"], "membrane");
    EXPECT_EQ(json["noData"]["sources"][0]["input"], "rainier.tif");
    EXPECT_EQ(json["noData"]["sources"][0]["sourceValue"], -32768);
    EXPECT_EQ(json["noData"]["sources"][0]["samples"], 9033);
    EXPECT_EQ(json["noData"]["sources"][0]["overBeneath"], 0);
    EXPECT_EQ(json["levels"].size(), 5U);
    EXPECT_EQ(json["levels"][0]["sampleStep"], 16);
    EXPECT_EQ(json["source"]["reader"], "oiio");
    EXPECT_EQ(json["build"]["tool"], "terrain-build");
}

// Each source's no-data value (issue 52): written per source; a manifest from before, whose
// entries lack it, read back with the pyramid's value where it has one source (a plane's).
TEST_F(PyramidFormat, ManifestNoDataValuePerSource) {
    PyramidManifest m = sampleManifest();
    m.noData.sources.front().sourceValue.reset();  // declared none: written as null
    auto back = fromJson(toJson(m), "test");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back.value(), m);
    EXPECT_TRUE(nlohmann::json::parse(toJson(m))["noData"]["sources"][0]["sourceValue"].is_null());

    auto older = nlohmann::json::parse(toJson(sampleManifest()));
    older["noData"]["sources"][0].erase("sourceValue");
    auto read = fromJson(older.dump(), "older");
    ASSERT_TRUE(read.ok()) << read.error().message;
    const ManifestSourceNoData& source = read.value().noData.sources.front();
    EXPECT_TRUE(source.sourceValueRecorded);
    EXPECT_EQ(source.sourceValue, -32768.0);
    EXPECT_EQ(read.value(), sampleManifest());
}

TEST_F(PyramidFormat, ManifestErrors) {
    // No manifest.
    auto missing = readManifest(m_dir);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().message, m_dir.string() + ": not a pyramid: no manifest.json");
    auto noFolder = readManifest(m_dir / "nope");
    ASSERT_FALSE(noFolder.ok());
    EXPECT_TRUE(contains(noFolder.error().message, (m_dir / "nope").string()));

    const fs::path file = m_dir / "manifest.json";
    const std::string good = toJson(sampleManifest());
    const auto errorFor = [&](const std::string& text) {
        writeText(file, text);
        auto r = readManifest(m_dir);
        EXPECT_FALSE(r.ok());
        return r.ok() ? std::string() : r.error().message;
    };
    auto edited = [&](auto&& edit) {
        auto j = nlohmann::ordered_json::parse(good);
        edit(j);
        return j.dump();
    };

    std::string e = errorFor("{ \"format\": ");
    EXPECT_TRUE(contains(e, file.string() + ": not valid JSON")) << e;
    // A number JSON cannot hold (nlohmann throws out_of_range, not parse_error: found by
    // fuzz-manifest, tests/fuzz/manifest/json-number-overflow).
    e = errorFor("1E7777777777");
    EXPECT_TRUE(contains(e, file.string() + ": not valid JSON")) << e;
    e = errorFor("");
    EXPECT_TRUE(contains(e, "not valid JSON")) << e;
    e = errorFor(edited([](auto& j) { j["format"] = "gltf"; }));
    EXPECT_TRUE(contains(e, file.string() + ": not a pyramid manifest: \"format\" is \"gltf\""))
        << e;
    e = errorFor("[1, 2]");
    EXPECT_TRUE(contains(e, "not a pyramid manifest")) << e;
    // Version 1's block errors left out the tessellator's transition strips; versions 2
    // and 3 stored heights as floats; 4 (planar) and 5 (globe) stored them in ZIP parts;
    // 6 and 7 predicted no patch from its parent.
    for (const int old : {1, 2, 3, 4, 5, 6, 7}) {
        e = errorFor(edited([&](auto& j) { j["formatVersion"] = old; }));
        EXPECT_TRUE(contains(e, fmt::format("unsupported formatVersion {} (this program reads "
                                            "versions 8 (planar) and 9 (globe); rebuild the "
                                            "pyramid with terrain-build)",
                                            old)))
            << e;
    }
    // A planar manifest that claims the globe's version lacks the globe it would need.
    e = errorFor(edited([](auto& j) { j["formatVersion"] = 9; }));
    EXPECT_TRUE(contains(e, "field \"levels[0].presentShards\" must be present")) << e;
    e = errorFor(edited([](auto& j) { j["levels"][3]["patchesX"] = 4; }));
    EXPECT_TRUE(contains(e, "inconsistent layout: levels[3].patchesX is 4")) << e;
    EXPECT_TRUE(contains(e, "has 5")) << e;
    e = errorFor(edited([](auto& j) { j["levels"].erase(j["levels"].size() - 1); }));
    EXPECT_TRUE(contains(e, "inconsistent layout: 4 levels listed")) << e;
    e = errorFor(edited([](auto& j) { j["finestLevel"] = 5; }));
    EXPECT_TRUE(contains(e, "inconsistent layout: finestLevel is 5")) << e;
    e = errorFor(edited([](auto& j) { j["patchSamples"] = 100; }));
    EXPECT_TRUE(contains(e, "bad layout: patch size 100")) << e;
    e = errorFor(edited([](auto& j) { j["raster"].erase("height"); }));
    EXPECT_TRUE(contains(e, "field \"raster.height\" must be present")) << e;
    e = errorFor(edited([](auto& j) { j["levels"][1]["maxError"] = "big"; }));
    EXPECT_TRUE(contains(e, "field \"levels[1].maxError\" must be a number")) << e;
    e = errorFor(edited([](auto& j) { j["georeference"]["crsKind"] = "polar"; }));
    EXPECT_TRUE(contains(e, "georeference.crsKind")) << e;
    e = errorFor(edited([](auto& j) { j["georeference"]["pixelSizeX"] = 0; }));
    EXPECT_TRUE(contains(e, "pixel size")) << e;
    e = errorFor(edited([](auto& j) { j["noData"]["fill"] = "kriging"; }));
    EXPECT_TRUE(contains(e, "noData.fill")) << e;
    e = errorFor(edited([](auto& j) { j["noData"]["sources"][0]["overBeneath"] = 9034; }));
    EXPECT_TRUE(contains(e, "noData.sources")) << e;
    e = errorFor(edited([](auto& j) { j["levels"][4]["presentPatches"] = 101; }));
    EXPECT_TRUE(contains(e, "presentPatches")) << e;
}

TEST_F(PyramidFormat, WriteManifestRejectsInconsistentManifests) {
    PyramidManifest m = sampleManifest();
    m.levels[2].shardsX = 7;
    const Status s = writeManifest(m_dir, m);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.error().message, "levels[2].shardsX")) << s.error().message;
    EXPECT_FALSE(fs::exists(m_dir / "manifest.json"));

    const Status empty = writeManifest(m_dir, PyramidManifest{});  // no layout set
    ASSERT_FALSE(empty.ok());
    EXPECT_TRUE(contains(empty.error().message, "bad layout: raster of 0 × 0 samples"))
        << empty.error().message;
}

// ---------------------------------------------------------------------------------------
// Shards

class ShardRoundTrip : public PyramidFormat, public ::testing::WithParamInterface<bool> {};

TEST_P(ShardRoundTrip, BitExact) {
    const bool withMask = GetParam();
    // 60 × 45 samples in patches of 9: 8 × 6 patches at the finest level, shards of 3.
    const PyramidLayout layout = PyramidLayout::create(60, 45, 9, 4, 3).value();
    const ShardId s{layout.finestLevel(), 2, 1};  // a 2 × 3 edge shard
    ASSERT_EQ(layout.shardCountX(s), 2);
    const PatchId absent{s.level, 7, 4};
    const auto records = writeRandomShard(layout, s, withMask, {absent}, 7);
    ASSERT_EQ(records.size(), 5U);

    auto reader = PyramidReader::open(m_dir);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    EXPECT_EQ(reader.value().hasMask(), withMask);
    for (const PatchRecord& expected : records) {
        auto read = reader.value().readPatch(expected.id);
        ASSERT_TRUE(read.ok()) << read.error().message;
        expectSameRecord(expected, read.value());
        auto info = reader.value().patchInfo(expected.id);
        ASSERT_TRUE(info.ok());
        EXPECT_EQ(info.value(), read.value().info);
    }
    // The in-place variant reuses the record.
    PatchRecord reused;
    for (const PatchRecord& expected : records) {
        ASSERT_TRUE(reader.value().readPatch(expected.id, reused).ok());
        expectSameRecord(expected, reused);
    }
    EXPECT_EQ(reader.value().shardOpenings(), 1U);
}

TEST_P(ShardRoundTrip, FullSizePatches) {
    const bool withMask = GetParam();
    const PyramidLayout layout = PyramidLayout::create(1201, 1201).value();  // N 129, 10 × 10
    const ShardId s{4, 0, 0};
    const auto records = writeRandomShard(layout, s, withMask, {}, 11);
    ASSERT_EQ(records.size(), 100U);
    auto reader = PyramidReader::open(m_dir);
    ASSERT_TRUE(reader.ok()) << reader.error().message;
    for (const PatchRecord& expected : records) {
        auto read = reader.value().readPatch(expected.id);
        ASSERT_TRUE(read.ok()) << read.error().message;
        expectSameRecord(expected, read.value());
    }
}

TEST_P(ShardRoundTrip, EveryCompressionLevelAndUncompressed) {
    const bool withMask = GetParam();
    const PyramidLayout layout = PyramidLayout::create(60, 45, 9, 4, 3).value();
    const ShardId s{3, 1, 1};
    for (int level : {0, 1, 3, 19}) {
        ShardWriterOptions options;
        options.compressionLevel = level;
        const auto records = writeRandomShard(layout, s, withMask, {}, 13, options);
        auto reader = PyramidReader::open(m_dir);
        ASSERT_TRUE(reader.ok());
        for (const PatchRecord& expected : records) {
            auto read = reader.value().readPatch(expected.id);
            ASSERT_TRUE(read.ok()) << "level " << level << ": " << read.error().message;
            expectSameRecord(expected, read.value());
        }
    }
    ShardWriterOptions bad;
    bad.compressionLevel = 20;
    auto rejected = ShardWriter::create(m_dir / "x.exr", layout, s, withMask, bad);
    ASSERT_FALSE(rejected.ok());
    EXPECT_TRUE(contains(rejected.error().message, "compression level 20: must be from 0"))
        << rejected.error().message;
}

// A builder encodes patches on its threads (encodePatch) and writes them in order
// (writeEncoded): the shard file is byte for byte the one writePatch writes, with a mask or
// without, compressed or not, with parent samples to predict from.
TEST_P(ShardRoundTrip, EncodedOnThreadsWritesTheSameBytes) {
    const bool withMask = GetParam();
    const PyramidLayout layout = PyramidLayout::create(60, 45, 9, 4, 3).value();
    const ShardId s{layout.finestLevel(), 1, 1};
    std::mt19937 rng(17);
    std::vector<PatchRecord> records;
    std::vector<std::vector<float>> parents;
    const int parentSide = (layout.tileSamples() - 1) / 2;
    std::uniform_real_distribution<float> height(-500.0f, 9000.0f);
    for (int ty = 0; ty < layout.shardCountY(s); ++ty)
        for (int tx = 0; tx < layout.shardCountX(s); ++tx) {
            const PatchId id{s.level, layout.shardFirstX(s) + tx, layout.shardFirstY(s) + ty};
            records.push_back(randomRecord(layout, id, withMask, rng));
            std::vector<float>& parent = parents.emplace_back();
            if (ty == 0) continue;  // some patches without parent samples
            for (int j = 0; j < parentSide * parentSide; ++j) parent.push_back(height(rng));
        }
    for (int level : {0, 3}) {
        ShardWriterOptions options;
        options.compressionLevel = level;
        const fs::path direct = m_dir / fmt::format("direct{}.exr", level);
        const fs::path encoded = m_dir / fmt::format("encoded{}.exr", level);
        {
            auto writer = ShardWriter::create(direct, layout, s, withMask, options);
            ASSERT_TRUE(writer.ok()) << writer.error().message;
            for (std::size_t i = 0; i < records.size(); ++i)
                ASSERT_TRUE(writer.value().writePatch(records[i], parents[i]).ok());
            ASSERT_TRUE(writer.value().finish().ok());
        }
        {
            std::vector<EncodedPatch> patches(records.size());
            std::vector<std::thread> threads;
            for (std::size_t i = 0; i < records.size(); ++i)
                threads.emplace_back([&, i] {
                    encodePatch(records[i], parents[i], layout, withMask, options, patches[i]);
                });
            for (std::thread& t : threads) t.join();
            auto writer = ShardWriter::create(encoded, layout, s, withMask, options);
            ASSERT_TRUE(writer.ok()) << writer.error().message;
            for (const EncodedPatch& patch : patches)
                ASSERT_TRUE(writer.value().writeEncoded(patch).ok());
            ASSERT_TRUE(writer.value().finish().ok());
        }
        const std::vector<char> expected = readBytes(direct), actual = readBytes(encoded);
        ASSERT_FALSE(expected.empty());
        EXPECT_TRUE(expected == actual) << "compression level " << level;
    }
}

// The payload codec does its job: smooth whole-metre terrain, with a hole in its mask,
// takes a fraction of its stored size once zstd-compressed, and both read back bit exact.
TEST_F(PyramidFormat, SmoothPatchesCompressSeveralTimesOver) {
    const PyramidLayout layout = PyramidLayout::create(1025, 1025).value();
    const ShardId s{layout.finestLevel(), 0, 0};
    const int tile = layout.tileSamples();
    std::vector<PatchRecord> records;
    for (int ty = 0; ty < 2; ++ty)
        for (int tx = 0; tx < 2; ++tx) {
            PatchRecord r;
            r.id = PatchId{s.level, tx, ty};
            r.heights.resize(static_cast<std::size_t>(tile * tile));
            r.valid.assign(r.heights.size(), 1);
            for (int j = 0; j < tile; ++j)
                for (int i = 0; i < tile; ++i) {
                    const double x = tx * 128 + i, y = ty * 128 + j;
                    r.heights[static_cast<std::size_t>(j * tile + i)] = static_cast<float>(
                        std::round(1200.0 + 300.0 * std::sin(x / 37.0) * std::cos(y / 29.0)));
                    if (std::hypot(i - 60, j - 40) < 12)
                        r.valid[static_cast<std::size_t>(j * tile + i)] = 0;
                }
            r.blockErrors.assign(
                static_cast<std::size_t>(layout.blocksPerSide() * layout.blocksPerSide()),
                BlockErrors{0.5f, 1.0f, 2.0f, 4.0f});
            r.info.present = true;
            r.info.approxError = r.info.error = 3.0f;
            summariseDrawnSamples(layout, r.heights, r.valid, r.info);
            records.push_back(r);
        }
    std::uintmax_t bytes[2] = {};
    for (const int level : {0, 3}) {
        ShardWriterOptions options;
        options.compressionLevel = level;
        auto writer = ShardWriter::create(m_dir / layout.shardPath(s), layout, s, true, options);
        ASSERT_TRUE(writer.ok()) << writer.error().message;
        for (const PatchRecord& r : records) ASSERT_TRUE(writer.value().writePatch(r).ok());
        ASSERT_TRUE(writer.value().finish().ok());
        PyramidManifest manifest = PyramidManifest::forLayout(layout);
        manifest.noData.present = true;
        ASSERT_TRUE(writeManifest(m_dir, manifest).ok());
        bytes[level == 0 ? 0 : 1] = fs::file_size(m_dir / layout.shardPath(s));
        auto reader = PyramidReader::open(m_dir);
        ASSERT_TRUE(reader.ok());
        for (const PatchRecord& expected : records) {
            auto read = reader.value().readPatch(expected.id);
            ASSERT_TRUE(read.ok()) << "level " << level << ": " << read.error().message;
            EXPECT_EQ(read.value().heights, expected.heights);
            EXPECT_EQ(read.value().valid, expected.valid);
        }
    }
    EXPECT_GT(bytes[0], 4 * bytes[1]) << "stored " << bytes[0] << " B, zstd " << bytes[1] << " B";
}

INSTANTIATE_TEST_SUITE_P(Mask, ShardRoundTrip, ::testing::Bool(),
                         [](const auto& p) { return p.param ? "WithMask" : "NoMask"; });

TEST_F(PyramidFormat, AbsentOutsideAndMissing) {
    const PyramidLayout layout = PyramidLayout::create(60, 45, 9, 4, 3).value();
    const ShardId s{layout.finestLevel(), 0, 0};
    const PatchId absent{s.level, 1, 1};
    writeRandomShard(layout, s, false, {absent}, 3);
    auto reader = PyramidReader::open(m_dir);
    ASSERT_TRUE(reader.ok());
    const std::string shardFile = (m_dir / "L3/0/0.exr").string();
    EXPECT_EQ(reader.value().shardFile(absent).string(), shardFile);

    auto r = reader.value().readPatch(absent);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message,
              shardFile + ": patch L3 (1, 1): the patch is absent (it does not overlap the DEM)");
    auto info = reader.value().patchInfo(absent);
    ASSERT_TRUE(info.ok());
    EXPECT_EQ(info.value(), PatchInfo{});  // zeros

    r = reader.value().readPatch(PatchId{3, 8, 0});
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(
        contains(r.error().message, "patch L3 (8, 0) is outside the pyramid (level 3 has 8 × 6"))
        << r.error().message;
    r = reader.value().readPatch(PatchId{4, 0, 0});
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "levels 0 to 3")) << r.error().message;

    // Shard (1, 0) was never written.
    r = reader.value().readPatch(PatchId{3, 4, 2});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message,
              (m_dir / "L3/0/1.exr").string() + ": patch L3 (4, 2): the shard file is missing");
}

TEST_F(PyramidFormat, ForeignShardIsRejected) {
    const PyramidLayout layout = PyramidLayout::create(60, 45, 9, 4, 3).value();
    const ShardId s{layout.finestLevel(), 0, 0};
    writeRandomShard(layout, s, false, {}, 3);
    // Overwrite with a shard of other patch size at the same path.
    const PyramidLayout other = PyramidLayout::create(60, 45, 17, 4, 3).value();
    {
        auto w = ShardWriter::create(m_dir / layout.shardPath(s), other, ShardId{2, 0, 0}, false);
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE(w.value().finish().ok());
    }
    auto reader = PyramidReader::open(m_dir);
    ASSERT_TRUE(reader.ok());
    auto r = reader.value().readPatch(PatchId{3, 0, 0});
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message,
                         "L3/0/0.exr: patch L3 (0, 0): not a shard of this "
                         "pyramid: part 'patches' has terrain:tileSamples 19, expected 11"))
        << r.error().message;
    // A mask where the manifest has none.
    {
        auto w = ShardWriter::create(m_dir / layout.shardPath(s), layout, s, true);
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE(w.value().finish().ok());
    }
    auto again = PyramidReader::open(m_dir);
    r = again.value().readPatch(PatchId{3, 0, 0});
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "part 'patches' has terrain:mask 1, expected 0"))
        << r.error().message;
}

// Reads every patch of the shard with a fresh reader; each read must fail with an Error
// naming the file or return exactly what was written. Returns the number of failed reads.
int readAllOrFail(const fs::path& dir, const std::vector<PatchRecord>& records,
                  const std::string& shardFile, const std::string& context) {
    auto reader = PyramidReader::open(dir);
    EXPECT_TRUE(reader.ok());
    int failures = 0;
    for (const PatchRecord& expected : records) {
        auto read = reader.value().readPatch(expected.id);
        if (!read.ok()) {
            ++failures;
            EXPECT_TRUE(contains(read.error().message, shardFile))
                << context << ": " << read.error().message;
            continue;
        }
        SCOPED_TRACE(context);
        expectSameRecord(expected, read.value());
    }
    return failures;
}

TEST_F(PyramidFormat, FlippedByteInTheMiddle) {
    const PyramidLayout layout = PyramidLayout::create(1201, 1201).value();
    const ShardId s{4, 0, 0};
    const auto records = writeRandomShard(layout, s, true, {}, 5);
    const fs::path file = m_dir / layout.shardPath(s);
    std::vector<char> bytes = readBytes(file);
    bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x10);
    writeBytes(file, bytes, bytes.size());
    EXPECT_GE(readAllOrFail(m_dir, records, file.string(), "flip"), 1);
}

TEST_F(PyramidFormat, TruncatedToHalf) {
    const PyramidLayout layout = PyramidLayout::create(1201, 1201).value();
    const ShardId s{4, 0, 0};
    const auto records = writeRandomShard(layout, s, false, {}, 5);
    const fs::path file = m_dir / layout.shardPath(s);
    const std::vector<char> bytes = readBytes(file);
    writeBytes(file, bytes, bytes.size() / 2);
    EXPECT_GE(readAllOrFail(m_dir, records, file.string(), "half"), 1);
}

// meshoptimizer-style: a flipped bit in every byte of a small shard (a different bit from
// byte to byte), and every truncated prefix, is either detected or harmless; never a crash,
// never wrong data. The
// one-patch shard is the case where OpenEXR stores the patchInfo tile uncompressed (zlib
// would make it larger), so only the checksum can notice a flipped error bound.
class EveryDamage : public PyramidFormat, public ::testing::WithParamInterface<int> {};

TEST_P(EveryDamage, IsDetectedOrHarmless) {
    const int side = GetParam();  // patches per shard side
    const PyramidLayout layout =
        PyramidLayout::create(4 * side + 1, 4 * side + 1, 5, 4, side).value();
    const ShardId s{layout.finestLevel(), 0, 0};
    const std::vector<PatchId> absent =
        side > 1 ? std::vector<PatchId>{PatchId{s.level, 1, 0}} : std::vector<PatchId>{};
    const auto records = writeRandomShard(layout, s, true, absent, 9);
    const fs::path file = m_dir / layout.shardPath(s);
    const std::vector<char> original = readBytes(file);
    ASSERT_GT(original.size(), 500U);
    for (std::size_t i = 0; i < original.size(); ++i) {
        const unsigned bit = (i * 5) % 8;  // a different bit from byte to byte
        std::vector<char> bytes = original;
        bytes[i] = static_cast<char>(bytes[i] ^ (1U << bit));
        writeBytes(file, bytes, bytes.size());
        readAllOrFail(m_dir, records, file.string(),
                      "byte " + std::to_string(i) + " bit " + std::to_string(bit));
        if (HasFailure()) return;
    }
    for (std::size_t size = 0; size < original.size(); ++size) {
        writeBytes(file, original, size);
        const int failures =
            readAllOrFail(m_dir, records, file.string(), "truncated to " + std::to_string(size));
        EXPECT_GE(failures, 1) << "truncated to " << size;
        if (HasFailure()) return;
    }
}

INSTANTIATE_TEST_SUITE_P(ShardSides, EveryDamage, ::testing::Values(1, 2));

TEST_F(PyramidFormat, UnfinishedWriterLeavesNothing) {
    const PyramidLayout layout = PyramidLayout::create(60, 45, 9, 4, 3).value();
    const ShardId s{3, 0, 0};
    std::mt19937 rng(1);
    {
        auto writer = ShardWriter::create(m_dir / layout.shardPath(s), layout, s, false);
        ASSERT_TRUE(writer.ok());
        for (int x = 0; x < 3; ++x)  // completes the first row: tiles reach the file
            ASSERT_TRUE(
                writer.value().writePatch(randomRecord(layout, {3, x, 0}, false, rng)).ok());
        ShardWriter moved = std::move(writer).value();
        ASSERT_TRUE(moved.writePatch(randomRecord(layout, {3, 0, 1}, false, rng)).ok());
    }
    const fs::path folder = m_dir / "L3" / "0";
    ASSERT_TRUE(fs::is_directory(folder));
    EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 0);
}

TEST_F(PyramidFormat, WriteFailureIsAnError) {
    // A file size limit makes write(2) fail with EFBIG, as a full disk fails with ENOSPC:
    // the same path through the stream. SIGXFSZ would otherwise end the process.
    const PyramidLayout layout = PyramidLayout::create(1201, 1201).value();
    const ShardId s{4, 0, 0};
    const fs::path path = m_dir / layout.shardPath(s);
    std::mt19937 rng(2);
    rlimit saved{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limited = saved;
    limited.rlim_cur = 64 * 1024;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
    Status failed;
    {
        auto writer = ShardWriter::create(path, layout, s, false);
        ASSERT_TRUE(writer.ok());
        for (int y = 0; y < 10 && failed.ok(); ++y)
            for (int x = 0; x < 10 && failed.ok(); ++x)
                failed = writer.value().writePatch(randomRecord(layout, {4, x, y}, false, rng));
        if (failed.ok()) failed = writer.value().finish();
        if (!failed.ok()) {
            // Once failed, always failed.
            const Status again = writer.value().finish();
            EXPECT_FALSE(again.ok());
        }
    }
    ::setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, previous);
    ASSERT_FALSE(failed.ok());
    EXPECT_TRUE(contains(failed.error().message, path.string() + ": cannot write: File too large"))
        << failed.error().message;
    EXPECT_FALSE(fs::exists(path));
    EXPECT_EQ(std::distance(fs::directory_iterator(path.parent_path()), fs::directory_iterator()),
              0);
}

TEST_F(PyramidFormat, TinyPyramidReadsBackAtEveryLevel) {
    for (bool noData : {false, true}) {
        test::TinyPyramidOptions options;
        options.withNoData = noData;
        options.absent = [](const PatchId& id) { return id.level == 3 && id.x == 4 && id.y == 3; };
        const fs::path dir = m_dir / (noData ? "mask" : "plain");
        auto written = test::writeTinyPyramid(dir, options);
        ASSERT_TRUE(written.ok()) << written.error().message;
        auto reader = PyramidReader::open(dir);
        ASSERT_TRUE(reader.ok()) << reader.error().message;
        const PyramidLayout& layout = reader.value().layout();
        ASSERT_EQ(layout.finestLevel(), 3);  // 37 × 29 in patches of 9: 5 × 4
        test::TinyPyramid tiny(layout, options);
        for (int l = 0; l <= layout.finestLevel(); ++l)
            for (std::int64_t y = 0; y < layout.patchesY(l); ++y)
                for (std::int64_t x = 0; x < layout.patchesX(l); ++x) {
                    const PatchId id{l, x, y};
                    auto read = reader.value().readPatch(id);
                    if (tiny.isAbsent(id)) {
                        EXPECT_FALSE(read.ok());
                        continue;
                    }
                    ASSERT_TRUE(read.ok()) << read.error().message;
                    expectSameRecord(tiny.patch(id), read.value());
                }
        EXPECT_EQ(reader.value().manifest().levels[3].presentPatches, 19);
    }
}

TEST_F(PyramidFormat, ReaderLruAcrossMoreShardsThanItsCapacity) {
    test::TinyPyramidOptions options;
    options.shardPatches = 1;  // one patch per shard: 20 shards at the finest level
    ASSERT_TRUE(test::writeTinyPyramid(m_dir, options).ok());
    auto opened = PyramidReader::open(m_dir, 3);
    ASSERT_TRUE(opened.ok());
    PyramidReader& reader = opened.value();
    const PyramidLayout& layout = reader.layout();
    test::TinyPyramid tiny(layout, options);
    const int L = layout.finestLevel();
    ASSERT_EQ(layout.shardCount(L), 20);
    for (int pass = 0; pass < 2; ++pass)
        for (std::int64_t y = 0; y < layout.patchesY(L); ++y)
            for (std::int64_t x = 0; x < layout.patchesX(L); ++x) {
                auto read = reader.readPatch({L, x, y});
                ASSERT_TRUE(read.ok()) << read.error().message;
                expectSameRecord(tiny.patch({L, x, y}), read.value());
                ASSERT_LE(reader.openShards(), 3);
            }
    EXPECT_EQ(reader.openShards(), 3);
    EXPECT_EQ(reader.shardOpenings(), 40U);  // every shard missed in both passes
    // The three most recent stay open: no reopening while cycling through them.
    for (int i = 0; i < 10; ++i)
        for (std::int64_t x = 2; x < 5; ++x) ASSERT_TRUE(reader.readPatch({L, x, 3}).ok());
    EXPECT_EQ(reader.shardOpenings(), 40U);
    // The least recently used goes first: touching (2, 3) keeps it; (0, 0) evicts (3, 3).
    ASSERT_TRUE(reader.readPatch({L, 2, 3}).ok());
    ASSERT_TRUE(reader.readPatch({L, 0, 0}).ok());
    ASSERT_TRUE(reader.readPatch({L, 2, 3}).ok());
    EXPECT_EQ(reader.shardOpenings(), 41U);
    ASSERT_TRUE(reader.readPatch({L, 3, 3}).ok());
    EXPECT_EQ(reader.shardOpenings(), 42U);
}

// The bytes of the payload a shard file holds for its patch tile (tx, ty), read with OpenEXR
// itself: the deep tile's sample count (one 32-bit word a sample, no OpenEXR compression).
std::uint64_t payloadBytesInShard(const fs::path& shard, int tx, int ty) {
    Imf::MultiPartInputFile file(shard.c_str());
    Imf::DeepTiledInputPart part(file, 0);
    EXPECT_EQ(part.header().name(), "patches");
    unsigned int count = 0;
    Imf::DeepFrameBuffer frame;
    // Strides of 0: every pixel of the window lands on `count` (a tile is one pixel).
    frame.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(&count), 0, 0));
    part.setFrameBuffer(frame);
    part.readPixelSampleCounts(tx, tx, ty, ty);
    return std::uint64_t{count} * sizeof(std::uint32_t);
}

TEST_F(PyramidFormat, TheStoredBytesReadAreThePayloadsInTheShardFiles) {
    test::TinyPyramidOptions options;
    options.shardPatches = 1;  // one patch per shard: its tile is (0, 0)
    options.withNoData = true;
    ASSERT_TRUE(test::writeTinyPyramid(m_dir, options).ok());
    auto opened = PyramidReader::open(m_dir);
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    PyramidReader& reader = opened.value();
    const PyramidLayout& layout = reader.layout();
    EXPECT_EQ(reader.storedBytesRead(), 0U);
    std::uint64_t expected = 0, shardBytes = 0;
    for (int l = 0; l <= layout.finestLevel(); ++l)
        for (std::int64_t y = 0; y < layout.patchesY(l); ++y)
            for (std::int64_t x = 0; x < layout.patchesX(l); ++x) {
                const PatchId id{l, x, y};
                const std::uint64_t before = reader.storedBytesRead();
                ASSERT_TRUE(reader.readPatch(id).ok());
                const std::uint64_t payload = payloadBytesInShard(reader.shardFile(id), 0, 0);
                EXPECT_GT(payload, 0U);
                EXPECT_EQ(reader.storedBytesRead() - before, payload) << "L" << l;
                expected += payload;
                shardBytes += fs::file_size(reader.shardFile(id));
            }
    EXPECT_EQ(reader.storedBytesRead(), expected);
    // The rest of each file is its headers and tables: most of a tiny patch's shard.
    EXPECT_LT(expected, shardBytes);
    // A patch read again is read again.
    ASSERT_TRUE(reader.readPatch({0, 0, 0}).ok());
    EXPECT_EQ(reader.storedBytesRead(),
              expected + payloadBytesInShard(reader.shardFile({0, 0, 0}), 0, 0));
}

}  // namespace
}  // namespace terrain::io
