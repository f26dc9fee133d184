// Height rasters written as GeoTIFF, 16-bit PNG and OpenEXR read back through
// OpenImageIO; the GeoTIFF georeference read back with libtiff (readGeoTiffGeoreference)
// and, where gdal-bin is installed, with gdalinfo. Failures leave no file behind.
#include "terrain/base/AtomicFile.h"
#include "terrain/dem/GeoTiffGeoreference.h"
#include "terrain/dem/HeightImageWriter.h"
#include "terrain/source/ProceduralTerrain.h"
#include "terrain/dem/RgbaImageWriter.h"

#include <OpenImageIO/imageio.h>
#include "TempFolder.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;

class HeightImageWriterTest : public ::testing::Test {
protected:
    void SetUp() override {
        // A window that is not a multiple of the 256² tiles, with the fault, of the DEM.
        ProceduralTerrainParameters p;
        Result<ProceduralTerrain> t = ProceduralTerrain::create(p);
        ASSERT_TRUE(t.ok());
        m_heights.resize(static_cast<std::size_t>(m_width * m_height));
        t.value().fillWindow(500, 300, m_width, m_height, m_heights);
    }

    // Names in the folder: after any write, only finished files, never a temporary.
    std::vector<std::string> entries(const fs::path& dir) const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir))
            names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    test::TempFolder m_tmp;
    fs::path m_dir = m_tmp.path();
    std::int64_t m_width = 300;
    std::int64_t m_height = 270;
    std::vector<float> m_heights;
};

struct ReadBack {
    OIIO::ImageSpec spec;
    std::vector<float> floats;
    std::vector<std::uint16_t> uint16s;
    std::vector<std::uint8_t> uint8s;
};

ReadBack readBack(const fs::path& path, OIIO::TypeDesc type) {
    ReadBack r;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path.string(), &config);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return r;
    r.spec = in->spec();
    const std::size_t n = static_cast<std::size_t>(r.spec.width) *
                          static_cast<std::size_t>(r.spec.height) *
                          static_cast<std::size_t>(r.spec.nchannels);
    bool ok = false;
    if (type == OIIO::TypeDesc::FLOAT) {
        r.floats.resize(n);
        ok = in->read_image(0, 0, 0, -1, type, r.floats.data());
    } else if (type == OIIO::TypeDesc::UINT16) {
        r.uint16s.resize(n);
        ok = in->read_image(0, 0, 0, -1, type, r.uint16s.data());
    } else {
        r.uint8s.resize(n);
        ok = in->read_image(0, 0, 0, -1, type, r.uint8s.data());
    }
    EXPECT_TRUE(ok) << in->geterror();
    return r;
}

TEST_F(HeightImageWriterTest, FormatComesFromTheExtension) {
    EXPECT_EQ(heightImageFormatFor("a/b.tif").value(), HeightImageFormat::GeoTiff);
    EXPECT_EQ(heightImageFormatFor("b.TIFF").value(), HeightImageFormat::GeoTiff);
    EXPECT_EQ(heightImageFormatFor("b.png").value(), HeightImageFormat::Png16);
    EXPECT_EQ(heightImageFormatFor("b.Exr").value(), HeightImageFormat::Exr);
    const auto bad = heightImageFormatFor("dem.bmp");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("dem.bmp"), std::string::npos);
    EXPECT_NE(bad.error().message.find(".bmp"), std::string::npos);
    EXPECT_FALSE(heightImageFormatFor("dem").ok());
}

TEST_F(HeightImageWriterTest, GeoTiffRoundTripsExactlyWithItsGeoreference) {
    for (const TiffCompression compression : {TiffCompression::Deflate, TiffCompression::None}) {
        const fs::path path = m_dir / "dem.tif";
        HeightImageOptions options;
        options.tiffCompression = compression;
        options.georeference = Georeference{1500.0, 30750.0 - 9000.0, 30.0, 30.0, 0};
        const auto summary = writeHeightImage(path, m_width, m_height, m_heights, options);
        ASSERT_TRUE(summary.ok()) << summary.error().message;
        EXPECT_EQ(summary.value().format, HeightImageFormat::GeoTiff);
        EXPECT_EQ(summary.value().minHeightM,
                  *std::min_element(m_heights.begin(), m_heights.end()));
        EXPECT_EQ(summary.value().maxHeightM,
                  *std::max_element(m_heights.begin(), m_heights.end()));
        EXPECT_FALSE(summary.value().bigTiff);

        const ReadBack r = readBack(path, OIIO::TypeDesc::FLOAT);
        EXPECT_EQ(r.spec.width, m_width);
        EXPECT_EQ(r.spec.height, m_height);
        EXPECT_EQ(r.spec.nchannels, 1);
        EXPECT_EQ(r.spec.format, OIIO::TypeDesc::FLOAT);
        EXPECT_EQ(r.spec.tile_width, 256);
        EXPECT_EQ(r.spec.tile_height, 256);
        ASSERT_EQ(r.floats.size(), m_heights.size());
        EXPECT_EQ(std::memcmp(r.floats.data(), m_heights.data(), m_heights.size() * sizeof(float)),
                  0);

        // OpenImageIO 2.4 does not expose the GeoTIFF tags; libtiff reads them.
        const Result<Georeference> geo = readGeoTiffGeoreference(path);
        ASSERT_TRUE(geo.ok()) << geo.error().message;
        EXPECT_EQ(geo.value(), *options.georeference);
        EXPECT_EQ(entries(m_dir), std::vector<std::string>{"dem.tif"});
    }
}

TEST_F(HeightImageWriterTest, GeoTiffCarriesAnEpsgCode) {
    const fs::path path = m_dir / "utm.tiff";
    HeightImageOptions options;
    options.georeference = Georeference{500000.0, 5200000.0, 10.0, 10.0, 32610};
    ASSERT_TRUE(writeHeightImage(path, m_width, m_height, m_heights, options).ok());
    const Result<Georeference> geo = readGeoTiffGeoreference(path);
    ASSERT_TRUE(geo.ok()) << geo.error().message;
    EXPECT_EQ(geo.value(), *options.georeference);
}

// gdal-bin is only a checking tool here: skip where it is missing.
TEST_F(HeightImageWriterTest, GdalReadsTheGeoTiffGeoreference) {
    if (std::system("command -v gdalinfo > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "gdalinfo not installed";
    const fs::path path = m_dir / "gdal.tif";
    HeightImageOptions options;
    options.georeference = Georeference{1500.0, 21750.0, 30.0, 30.0, 0};
    ASSERT_TRUE(writeHeightImage(path, m_width, m_height, m_heights, options).ok());
    const std::string command = "gdalinfo -json '" + path.string() + "' 2>/dev/null";
    FILE* pipe = ::popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string text;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        text.append(buffer, n);
    ASSERT_EQ(::pclose(pipe), 0) << text;
    const nlohmann::json info = nlohmann::json::parse(text);
    const std::vector<double> transform = info.at("geoTransform").get<std::vector<double>>();
    EXPECT_EQ(transform, (std::vector<double>{1500.0, 30.0, 0.0, 21750.0, 0.0, -30.0}));
    EXPECT_EQ(info.at("size").get<std::vector<int>>(), (std::vector<int>{300, 270}));
    EXPECT_EQ(info.at("bands").at(0).at("type").get<std::string>(), "Float32");
    EXPECT_EQ(info.at("bands").at(0).at("block").get<std::vector<int>>(),
              (std::vector<int>{256, 256}));
}

TEST_F(HeightImageWriterTest, BigTiffCanBeForced) {
    const fs::path path = m_dir / "big.tif";
    HeightImageOptions options;
    options.bigTiff = BigTiffMode::Always;
    const auto summary = writeHeightImage(path, m_width, m_height, m_heights, options);
    ASSERT_TRUE(summary.ok()) << summary.error().message;
    EXPECT_TRUE(summary.value().bigTiff);
    std::ifstream file(path, std::ios::binary);
    char header[4] = {};
    file.read(header, 4);
    EXPECT_EQ(header[2], 43);  // BigTIFF version number (a classic TIFF has 42)
    const ReadBack r = readBack(path, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(std::memcmp(r.floats.data(), m_heights.data(), m_heights.size() * sizeof(float)), 0);
}

TEST_F(HeightImageWriterTest, ExrRoundTripsExactlyInChannelY) {
    const fs::path path = m_dir / "dem.exr";
    const auto summary = writeHeightImage(path, m_width, m_height, m_heights);
    ASSERT_TRUE(summary.ok()) << summary.error().message;
    const ReadBack r = readBack(path, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(r.spec.nchannels, 1);
    EXPECT_EQ(r.spec.channelnames, std::vector<std::string>{"Y"});
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(std::memcmp(r.floats.data(), m_heights.data(), m_heights.size() * sizeof(float)), 0);
}

TEST_F(HeightImageWriterTest, PngRoundTripsWithinHalfAStep) {
    const fs::path path = m_dir / "dem.png";
    const auto summary = writeHeightImage(path, m_width, m_height, m_heights);
    ASSERT_TRUE(summary.ok()) << summary.error().message;
    ASSERT_TRUE(summary.value().png.has_value());
    const PngQuantisation q = *summary.value().png;
    EXPECT_EQ(q.scaleM, 0.1);
    EXPECT_EQ(q.offsetM, std::floor(*std::min_element(m_heights.begin(), m_heights.end())));
    EXPECT_EQ(q.clampedSamples, 0U);
    const ReadBack r = readBack(path, OIIO::TypeDesc::UINT16);
    EXPECT_EQ(r.spec.format, OIIO::TypeDesc::UINT16);
    EXPECT_EQ(r.spec.nchannels, 1);
    ASSERT_EQ(r.uint16s.size(), m_heights.size());
    for (std::size_t i = 0; i < m_heights.size(); ++i) {
        const double back = q.offsetM + r.uint16s[i] * q.scaleM;
        ASSERT_LE(std::abs(back - m_heights[i]), q.scaleM / 2 + 1e-9) << "sample " << i;
    }
}

TEST_F(HeightImageWriterTest, PngHonoursScaleAndOffsetAndCountsClamping) {
    const fs::path path = m_dir / "fixed.png";
    const std::vector<float> heights = {-5.0F, 0.0F, 1.0F, 6553.5F, 7000.0F, NAN};
    HeightImageOptions options;
    options.pngScaleM = 0.5;
    options.pngOffsetM = 0.0;
    const auto summary = writeHeightImage(path, 3, 2, heights, options);
    ASSERT_TRUE(summary.ok()) << summary.error().message;
    EXPECT_EQ(summary.value().png->offsetM, 0.0);
    EXPECT_EQ(summary.value().png->clampedSamples, 2U);  // −5 and NaN
    EXPECT_EQ(summary.value().nonFiniteSamples, 1U);
    const ReadBack r = readBack(path, OIIO::TypeDesc::UINT16);
    EXPECT_EQ(r.uint16s, (std::vector<std::uint16_t>{0, 0, 2, 13107, 14000, 0}));
}

TEST_F(HeightImageWriterTest, SourceIsReadInBandsOfRows) {
    // Every format asks for consecutive bands no taller than a tile row / bandRows.
    for (const char* name : {"bands.tif", "bands.png", "bands.exr"}) {
        std::int64_t nextRow = 0;
        std::int64_t tallest = 0;
        int passes = 0;
        const HeightRowSource source = [&](std::int64_t firstRow, std::int64_t rowCount,
                                           std::span<float> out) {
            if (firstRow == 0) {
                ++passes;
                nextRow = 0;
            }
            EXPECT_EQ(firstRow, nextRow);
            EXPECT_EQ(out.size(), static_cast<std::size_t>(rowCount * m_width));
            std::copy_n(m_heights.begin() + firstRow * m_width, rowCount * m_width, out.begin());
            nextRow = firstRow + rowCount;
            tallest = std::max(tallest, rowCount);
        };
        HeightImageOptions options;
        options.bandRows = 100;
        double lastProgress = 0.0;
        options.progress = [&](double f) {
            EXPECT_GE(f, lastProgress);
            lastProgress = f;
        };
        const auto summary = writeHeightImage(m_dir / name, m_width, m_height, source, options);
        ASSERT_TRUE(summary.ok()) << summary.error().message;
        EXPECT_EQ(nextRow, m_height) << name;
        EXPECT_LE(tallest, 256) << name;
        EXPECT_DOUBLE_EQ(lastProgress, 1.0) << name;
        EXPECT_EQ(passes, std::string(name) == "bands.png" ? 2 : 1)
            << name;  // PNG finds its offset first
    }
}

TEST_F(HeightImageWriterTest, UnknownExtensionIsAnErrorAndWritesNothing) {
    const fs::path path = m_dir / "dem.bmp";
    const auto result = writeHeightImage(path, m_width, m_height, m_heights);
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find(path.string()), std::string::npos)
        << result.error().message;
    EXPECT_TRUE(entries(m_dir).empty());
}

TEST_F(HeightImageWriterTest, UnwritableFolderIsAnErrorNamingThePathAndLeavesNothing) {
    for (const char* name : {"dem.tif", "dem.png", "dem.exr"}) {
        const fs::path missing = m_dir / "no-such-folder" / name;
        const auto result = writeHeightImage(missing, m_width, m_height, m_heights);
        ASSERT_FALSE(result.ok()) << name;
        EXPECT_NE(result.error().message.find(missing.string()), std::string::npos)
            << result.error().message;
        EXPECT_NE(result.error().message.find("No such file"), std::string::npos)
            << result.error().message;

        // A regular file where the folder should be.
        std::ofstream(m_dir / "plain-file") << "x";
        const fs::path underFile = m_dir / "plain-file" / name;
        const auto result2 = writeHeightImage(underFile, m_width, m_height, m_heights);
        ASSERT_FALSE(result2.ok());
        EXPECT_NE(result2.error().message.find(underFile.string()), std::string::npos);
        EXPECT_EQ(entries(m_dir), std::vector<std::string>{"plain-file"});
    }
    if (::geteuid() != 0) {  // root may write anywhere
        const fs::path locked = m_dir / "locked";
        fs::create_directory(locked);
        ::chmod(locked.c_str(), 0555);
        const auto result = writeHeightImage(locked / "dem.tif", m_width, m_height, m_heights);
        ::chmod(locked.c_str(), 0755);
        ASSERT_FALSE(result.ok());
        EXPECT_NE(result.error().message.find((locked / "dem.tif").string()), std::string::npos);
        EXPECT_TRUE(entries(locked).empty());
    }
}

TEST_F(HeightImageWriterTest, FailedWriteKeepsTheOldFileAndRemovesTheTemporary) {
    const fs::path path = m_dir / "keep.tif";
    std::ofstream(path) << "old contents";
    fs::path seenTemporary;
    const Status status = writeAtomically(path, [&](const fs::path& temporary) -> Status {
        seenTemporary = temporary;
        EXPECT_EQ(temporary.parent_path(), path.parent_path());
        EXPECT_EQ(temporary.extension(), ".tif");  // libraries pick formats from it
        EXPECT_TRUE(fs::exists(temporary));
        std::ofstream(temporary) << "half written";
        return Error{"keep.tif: simulated failure"};
    });
    ASSERT_FALSE(status.ok());
    EXPECT_FALSE(fs::exists(seenTemporary));
    std::ifstream in(path);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "old contents");
    EXPECT_EQ(entries(m_dir), std::vector<std::string>{"keep.tif"});
}

TEST_F(HeightImageWriterTest, SuccessfulWriteReplacesTheOldFile) {
    const fs::path path = m_dir / "replace.exr";
    std::ofstream(path) << "old contents";
    ASSERT_TRUE(writeHeightImage(path, m_width, m_height, m_heights).ok());
    const ReadBack r = readBack(path, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(r.spec.width, m_width);
    EXPECT_EQ(entries(m_dir), std::vector<std::string>{"replace.exr"});
}

TEST_F(HeightImageWriterTest, AtomicFileRemovesItsTemporaryWhenDropped) {
    fs::path temporary;
    {
        Result<AtomicFile> file = AtomicFile::create(m_dir / "x.csv");
        ASSERT_TRUE(file.ok());
        temporary = file.value().temporaryPath();
        EXPECT_TRUE(fs::exists(temporary));
        AtomicFile moved = std::move(file).value();
        EXPECT_EQ(moved.temporaryPath(), temporary);
    }
    EXPECT_FALSE(fs::exists(temporary));
    EXPECT_TRUE(entries(m_dir).empty());
}

TEST_F(HeightImageWriterTest, Rgba8PngRoundTrips) {
    const std::int64_t w = 7, h = 5;
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w * h * 4));
    for (std::size_t i = 0; i < pixels.size(); ++i)
        pixels[i] = static_cast<std::uint8_t>(i * 37 + 11);
    const fs::path path = m_dir / "frame.png";
    const Status status = writeRgba8Png(path, w, h, pixels);
    ASSERT_TRUE(status.ok()) << status.error().message;
    const ReadBack r = readBack(path, OIIO::TypeDesc::UINT8);
    EXPECT_EQ(r.spec.width, w);
    EXPECT_EQ(r.spec.height, h);
    EXPECT_EQ(r.spec.nchannels, 4);
    EXPECT_EQ(r.uint8s, pixels);  // row 0 of the buffer is the top row of the file
    const Status bad = writeRgba8Png(m_dir / "missing" / "frame.png", w, h, pixels);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("frame.png"), std::string::npos);
    EXPECT_EQ(entries(m_dir), std::vector<std::string>{"frame.png"});
}

}  // namespace
}  // namespace terrain::io
