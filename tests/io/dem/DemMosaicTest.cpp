// openDem with several inputs: GeoTIFF tiles written here (and halves of the real
// Rainier tile cut with GDALTranslate) mosaic back to the whole raster; inputs with
// another pixel size, CRS or grid are Errors naming the file.
#include "DemTestSupport.h"
#include "SharedData.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/dem/HeightImageWriter.h"
#include "terrain/source/ProceduralTerrain.h"

#include <gdal_priv.h>
#include <gdal_utils.h>

#include <cmath>

namespace terrain::io {
namespace {

using test::countDifferences;
using test::readAll;
using test::statsOf;
using test::TempDir;

class DemMosaicTest : public ::testing::Test {
protected:
    void SetUp() override {
        ProceduralTerrainParameters p;
        p.widthSamples = 300;
        p.heightSamples = 200;
        Result<ProceduralTerrain> t = ProceduralTerrain::create(p);
        ASSERT_TRUE(t.ok());
        m_heights.resize(static_cast<std::size_t>(kWidth * kHeight));
        t.value().fillWindow(0, 0, kWidth, kHeight, m_heights);
        m_whole = writeTile("whole.tif", 0, 0, kWidth, kHeight);
    }

    // Columns [x0, x0 + w) and rows [y0, y0 + h) of the heights as a GeoTIFF placed where
    // they lie in the whole raster (or with another pixel size / EPSG when given).
    std::string writeTile(const std::string& name, std::int64_t x0, std::int64_t y0, std::int64_t w,
                          std::int64_t h, double pixelSize = kPixel, int epsg = kEpsg,
                          double shiftX = 0.0) {
        std::vector<float> tile(static_cast<std::size_t>(w * h));
        for (std::int64_t r = 0; r < h; ++r)
            std::copy_n(m_heights.begin() + (y0 + r) * kWidth + x0, w, tile.begin() + r * w);
        HeightImageOptions options;
        options.georeference =
            Georeference{kOriginX + static_cast<double>(x0) * kPixel + shiftX,
                         kOriginY - static_cast<double>(y0) * kPixel, pixelSize, pixelSize, epsg};
        const std::string path = m_dir.file(name);
        const auto written = writeHeightImage(path, w, h, tile, options);
        EXPECT_TRUE(written.ok()) << written.error().message;
        return path;
    }

    std::unique_ptr<DemReader> mustOpen(const std::vector<std::string>& inputs) {
        Result<std::unique_ptr<DemReader>> reader = openDem(inputs);
        EXPECT_TRUE(reader.ok()) << reader.error().message;
        return reader.ok() ? std::move(reader).value() : nullptr;
    }

    static constexpr std::int64_t kWidth = 300;
    static constexpr std::int64_t kHeight = 200;
    static constexpr double kPixel = 10.0;
    static constexpr double kOriginX = 400000.0;
    static constexpr double kOriginY = 5100000.0;
    static constexpr int kEpsg = 32610;

    TempDir m_dir;
    std::vector<float> m_heights;
    std::string m_whole;
};

TEST_F(DemMosaicTest, TwoHalvesReadAsTheWhole) {
    const std::string west = writeTile("west.tif", 0, 0, 130, kHeight);
    const std::string east = writeTile("east.tif", 130, 0, kWidth - 130, kHeight);
    auto mosaic = mustOpen({west, east});
    ASSERT_TRUE(mosaic);
    const DemInfo& info = mosaic->info();
    EXPECT_EQ(info.readerName, "gdal");
    EXPECT_EQ(info.path, west);
    EXPECT_EQ(info.inputs, (std::vector<std::string>{west, east}));
    EXPECT_EQ(info.width, kWidth);
    EXPECT_EQ(info.height, kHeight);
    EXPECT_EQ(info.sampleType, "float32");
    EXPECT_TRUE(info.hasGeoreference);
    EXPECT_EQ(info.georeference.crsKind, CrsKind::Projected);
    EXPECT_EQ(info.georeference.epsg, kEpsg);
    EXPECT_DOUBLE_EQ(info.georeference.originX, kOriginX);
    EXPECT_DOUBLE_EQ(info.georeference.originY, kOriginY);
    EXPECT_DOUBLE_EQ(info.georeference.pixelSizeX, kPixel);
    const std::vector<float> all = readAll(*mosaic, 37);
    EXPECT_EQ(countDifferences(all, m_heights), 0U);
    test::expectRandomWindowsMatch(*mosaic, all, 25);
}

TEST_F(DemMosaicTest, FourQuadrantsInAnyOrderWithOverlap) {
    // Tiles share an edge row/column as SRTM tiles do; the order does not matter.
    const std::string nw = writeTile("nw.tif", 0, 0, 151, 101);
    const std::string ne = writeTile("ne.tif", 150, 0, 150, 101);
    const std::string sw = writeTile("sw.tif", 0, 100, 151, 100);
    const std::string se = writeTile("se.tif", 150, 100, 150, 100);
    auto mosaic = mustOpen({se, nw, sw, ne});
    ASSERT_TRUE(mosaic);
    EXPECT_EQ(mosaic->info().width, kWidth);
    EXPECT_EQ(mosaic->info().height, kHeight);
    EXPECT_DOUBLE_EQ(mosaic->info().georeference.originX, kOriginX);
    EXPECT_EQ(countDifferences(readAll(*mosaic), m_heights), 0U);
}

TEST_F(DemMosaicTest, UnnamedProjectedCrs) {
    // The writer's "unnamed projected CRS, metres" (EPSG 0) on both tiles is one CRS.
    const std::string west = writeTile("west.tif", 0, 0, 130, kHeight, kPixel, 0);
    const std::string east = writeTile("east.tif", 130, 0, kWidth - 130, kHeight, kPixel, 0);
    auto mosaic = mustOpen({west, east});
    ASSERT_TRUE(mosaic);
    EXPECT_EQ(mosaic->info().georeference.crsKind, CrsKind::Projected);
    EXPECT_EQ(mosaic->info().georeference.epsg, 0);
    EXPECT_EQ(countDifferences(readAll(*mosaic), m_heights), 0U);
}

TEST_F(DemMosaicTest, GapsReadAsNaN) {
    const std::string west = writeTile("west.tif", 0, 0, 100, kHeight);
    const std::string east = writeTile("east.tif", 200, 50, 100, 100);
    auto mosaic = mustOpen({west, east});
    ASSERT_TRUE(mosaic);
    EXPECT_EQ(mosaic->info().width, kWidth);
    const std::vector<float> all = readAll(*mosaic);
    for (std::int64_t y = 0; y < kHeight; ++y) {
        for (std::int64_t x = 0; x < kWidth; ++x) {
            const std::size_t i = static_cast<std::size_t>(y * kWidth + x);
            const bool covered = x < 100 || (x >= 200 && y >= 50 && y < 150);
            if (covered)
                ASSERT_EQ(all[i], m_heights[i]) << x << "," << y;
            else
                ASSERT_TRUE(std::isnan(all[i])) << x << "," << y;
        }
    }
}

TEST_F(DemMosaicTest, MismatchedPixelSizeNamesTheFile) {
    const std::string west = writeTile("west.tif", 0, 0, 150, kHeight);
    const std::string east = writeTile("east_20m.tif", 150, 0, 150, kHeight, 20.0);
    const auto mosaic = openDem({west, east});
    ASSERT_FALSE(mosaic.ok());
    const std::string& message = mosaic.error().message;
    EXPECT_TRUE(message.starts_with(east)) << message;
    EXPECT_NE(message.find("pixel size 20"), std::string::npos) << message;
    EXPECT_NE(message.find("10"), std::string::npos) << message;
}

TEST_F(DemMosaicTest, MismatchedCrsNamesTheFile) {
    const std::string west = writeTile("west.tif", 0, 0, 150, kHeight);
    const std::string east = writeTile("east_utm11.tif", 150, 0, 150, kHeight, kPixel, 32611);
    const auto mosaic = openDem({west, east});
    ASSERT_FALSE(mosaic.ok());
    const std::string& message = mosaic.error().message;
    EXPECT_TRUE(message.starts_with(east)) << message;
    EXPECT_NE(message.find("EPSG:32611"), std::string::npos) << message;
    EXPECT_NE(message.find("EPSG:32610"), std::string::npos) << message;
}

TEST_F(DemMosaicTest, MisalignedGridNamesTheFile) {
    const std::string west = writeTile("west.tif", 0, 0, 150, kHeight);
    const std::string east =
        writeTile("east_shifted.tif", 150, 0, 150, kHeight, kPixel, kEpsg, 3.0);
    const auto mosaic = openDem({west, east});
    ASSERT_FALSE(mosaic.ok());
    EXPECT_TRUE(mosaic.error().message.starts_with(east)) << mosaic.error().message;
    EXPECT_NE(mosaic.error().message.find("not aligned"), std::string::npos);
}

TEST_F(DemMosaicTest, UnreadableInputNamesTheFile) {
    const std::string west = writeTile("west.tif", 0, 0, 150, kHeight);
    const std::string missing = m_dir.file("missing.tif");
    auto mosaic = openDem({west, missing});
    ASSERT_FALSE(mosaic.ok());
    EXPECT_TRUE(mosaic.error().message.starts_with(missing)) << mosaic.error().message;

    const std::string garbage = m_dir.file("garbage.tif");
    test::writeBytes(garbage, std::vector<char>(5000, 'x'));
    mosaic = openDem({west, garbage});
    ASSERT_FALSE(mosaic.ok());
    EXPECT_TRUE(mosaic.error().message.starts_with(garbage)) << mosaic.error().message;

    mosaic = openDem({west, "procedural:size=257"});
    ASSERT_FALSE(mosaic.ok());
}

TEST(DemMosaicRealData, RainierHalvesCutWithGdalTranslate) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "srtm3_n46w122_rainier.tif");
    GDALAllRegister();
    TempDir dir;
    const auto cut = [&](const std::string& name, const char* x, const char* w) {
        const std::string out = dir.file(name);
        const char* argv[] = {"-srcwin", x, "0", w, "1201", "-q", nullptr};
        GDALTranslateOptions* options = GDALTranslateOptionsNew(const_cast<char**>(argv), nullptr);
        GDALDatasetH source = GDALOpen(path.c_str(), GA_ReadOnly);
        EXPECT_NE(source, nullptr);
        int usageError = 0;
        GDALDatasetH result = GDALTranslate(out.c_str(), source, options, &usageError);
        EXPECT_NE(result, nullptr);
        GDALClose(result);
        GDALClose(source);
        GDALTranslateOptionsFree(options);
        return out;
    };
    const std::string west = cut("west.tif", "0", "600");
    const std::string east = cut("east.tif", "600", "601");
    Result<std::unique_ptr<DemReader>> whole = test::openOne(path.string());
    Result<std::unique_ptr<DemReader>> mosaic = openDem({west, east});
    ASSERT_TRUE(whole.ok()) << whole.error().message;
    ASSERT_TRUE(mosaic.ok()) << mosaic.error().message;
    const DemInfo& info = mosaic.value()->info();
    EXPECT_EQ(info.width, 1201);
    EXPECT_EQ(info.height, 1201);
    EXPECT_EQ(info.sampleType, "int16");
    EXPECT_EQ(info.georeference.crsKind, CrsKind::Geographic);
    EXPECT_EQ(info.georeference.epsg, 4326);
    EXPECT_NEAR(info.georeference.originX, whole.value()->info().georeference.originX, 1e-9);
    EXPECT_NEAR(info.georeference.originY, whole.value()->info().georeference.originY, 1e-9);
    const std::vector<float> fromMosaic = readAll(*mosaic.value());
    EXPECT_EQ(countDifferences(fromMosaic, readAll(*whole.value())), 0U);
    EXPECT_EQ(statsOf(fromMosaic).nanCount, 9033U);
}

}  // namespace
}  // namespace terrain::io
