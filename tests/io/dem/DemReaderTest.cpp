// openDem on the real DEMs in ../shared/data (numbers from its SOURCES.md), on rasters
// this test writes in every supported sample type and layout, and on the procedural
// source; every reader's random windows agree with its whole read.
#include "DemTestSupport.h"
#include "SharedData.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/dem/HeightImageWriter.h"
#include "terrain/source/ProceduralTerrain.h"

#include <OpenImageIO/imageio.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <array>
#include <cstdint>
#include <numeric>
#include <tuple>

namespace terrain::io {
namespace {

using test::countDifferences;
using test::openOne;
using test::readAll;
using test::statsOf;
using test::TempDir;
namespace fs = std::filesystem;

constexpr double kArcSecond3 = 1.0 / 1200.0;

std::unique_ptr<DemReader> mustOpen(const std::string& path, const DemOpenOptions& options = {}) {
    Result<std::unique_ptr<DemReader>> reader = openOne(path, options);
    EXPECT_TRUE(reader.ok()) << reader.error().message;
    return reader.ok() ? std::move(reader).value() : nullptr;
}

// ---------------------------------------------------------------------------------------
// The real DEMs

TEST(DemReaderRealData, RainierGeoTiff) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "srtm3_n46w122_rainier.tif");
    auto reader = mustOpen(path.string());
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.readerName, "oiio");
    EXPECT_EQ(info.width, 1201);
    EXPECT_EQ(info.height, 1201);
    EXPECT_EQ(info.sampleType, "int16");
    ASSERT_TRUE(info.noDataValue.has_value());
    EXPECT_EQ(*info.noDataValue, -32768.0);
    EXPECT_TRUE(info.hasGeoreference);
    const Georeference& g = info.georeference;
    EXPECT_EQ(g.crsKind, CrsKind::Geographic);
    EXPECT_EQ(g.epsg, 4326);
    EXPECT_NEAR(g.originX, -122.000417, 1e-6);
    EXPECT_NEAR(g.originY, 47.000417, 1e-6);
    EXPECT_NEAR(g.pixelSizeX, 0.000833333, 1e-9);
    EXPECT_NEAR(g.pixelSizeY, 0.000833333, 1e-9);

    const std::vector<float> all = readAll(*reader);
    const auto stats = statsOf(all);
    EXPECT_EQ(stats.nanCount, 9033U);
    EXPECT_EQ(stats.min, 263.0F);
    EXPECT_EQ(stats.max, 4371.0F);
    test::expectRandomWindowsMatch(*reader, all);
}

TEST(DemReaderRealData, PugetSoundPngWithVerticalScale) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "puget_sound_1k.png");
    DemOpenOptions options;
    options.verticalScale = 0.1;
    auto reader = mustOpen(path.string(), options);
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.readerName, "oiio");
    EXPECT_EQ(info.width, 1025);
    EXPECT_EQ(info.height, 1025);
    EXPECT_EQ(info.sampleType, "uint16");
    EXPECT_FALSE(info.hasGeoreference);
    EXPECT_EQ(info.georeference.crsKind, CrsKind::Unknown);
    EXPECT_EQ(info.georeference.pixelSizeX, 1.0);
    EXPECT_EQ(info.georeference.originX, 0.0);
    EXPECT_EQ(info.vertical.scale, 0.1);
    // No spacing in the file: 1 m per sample, and the user is told with the flags to give.
    ASSERT_EQ(info.warnings.size(), 1U);
    EXPECT_TRUE(info.warnings[0].starts_with(path.string())) << info.warnings[0];
    EXPECT_NE(info.warnings[0].find("1 m per sample"), std::string::npos) << info.warnings[0];
    EXPECT_NE(info.warnings[0].find("--spacing"), std::string::npos) << info.warnings[0];
    EXPECT_FALSE(info.noDataValue.has_value());

    const std::vector<float> all = readAll(*reader);
    const auto stats = statsOf(all);
    EXPECT_EQ(stats.nanCount, 0U);
    EXPECT_EQ(stats.min, 0.0F);
    EXPECT_NEAR(stats.max, 4379.8, 1e-3);
    test::expectRandomWindowsMatch(*reader, all);
}

TEST(DemReaderRealData, SrtmHgtTile) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "srtm/N57E011.hgt");
    auto reader = mustOpen(path.string());
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.readerName, "hgt");
    EXPECT_EQ(info.width, 1201);
    EXPECT_EQ(info.height, 1201);
    EXPECT_EQ(info.sampleType, "int16");
    const Georeference& g = info.georeference;
    EXPECT_TRUE(info.hasGeoreference);
    EXPECT_EQ(g.crsKind, CrsKind::Geographic);
    EXPECT_EQ(g.epsg, 4326);
    EXPECT_DOUBLE_EQ(g.pixelSizeX, kArcSecond3);
    EXPECT_DOUBLE_EQ(g.originX, 11.0 - 0.5 * kArcSecond3);
    EXPECT_DOUBLE_EQ(g.originY, 58.0 + 0.5 * kArcSecond3);

    const std::vector<float> all = readAll(*reader);
    const auto stats = statsOf(all);
    EXPECT_EQ(stats.nanCount, 0U);
    EXPECT_EQ(stats.min, -6.0F);
    EXPECT_EQ(stats.max, 163.0F);
    const double zeros = static_cast<double>(stats.zeroCount) / static_cast<double>(all.size());
    EXPECT_NEAR(zeros, 0.86, 0.01);
    test::expectRandomWindowsMatch(*reader, all);
}

TEST(DemReaderRealData, KilaueaNetCdfUtm) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "kilauea_utm5n_30m.nc");
    auto reader = mustOpen(path.string());
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.readerName, "gdal");
    EXPECT_EQ(info.width, 857);
    EXPECT_EQ(info.height, 793);
    EXPECT_EQ(info.sampleType, "int16");
    ASSERT_TRUE(info.noDataValue.has_value());
    EXPECT_EQ(*info.noDataValue, -32768.0);
    const Georeference& g = info.georeference;
    EXPECT_TRUE(info.hasGeoreference);
    EXPECT_EQ(g.crsKind, CrsKind::Projected);
    EXPECT_NE(g.wkt.find("UTM zone 5N"), std::string::npos) << g.wkt;
    EXPECT_EQ(g.epsg, 0);  // a WKT without an EPSG code
    // Node coordinates 254340..280020 and 2129880..2153640: edges half a cell outside.
    EXPECT_DOUBLE_EQ(g.originX, 254340.0 - 15.0);
    EXPECT_DOUBLE_EQ(g.originY, 2153640.0 + 15.0);
    EXPECT_DOUBLE_EQ(g.pixelSizeX, 30.0);
    EXPECT_DOUBLE_EQ(g.pixelSizeY, 30.0);

    const std::vector<float> all = readAll(*reader);
    const auto stats = statsOf(all);
    EXPECT_EQ(stats.nanCount, 20656U);
    EXPECT_EQ(stats.zeroCount, 31962U);
    EXPECT_EQ(stats.min, 0.0F);
    EXPECT_EQ(stats.max, 1505.0F);
    test::expectRandomWindowsMatch(*reader, all);
}

TEST(DemReaderRealData, Etopo20GlobalNetCdfIsNorthUp) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "etopo20_global.nc");
    auto reader = mustOpen(path.string());
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.readerName, "gdal");
    EXPECT_EQ(info.width, 1081);
    EXPECT_EQ(info.height, 540);
    EXPECT_EQ(info.sampleType, "float32");
    const Georeference& g = info.georeference;
    EXPECT_TRUE(info.hasGeoreference);
    EXPECT_EQ(g.crsKind, CrsKind::Geographic);
    EXPECT_EQ(g.epsg, 4326);
    EXPECT_NEAR(g.pixelSizeX, 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(g.pixelSizeY, 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(g.originX, 20.0, 1e-5);  // cell centres from 20.1667 E
    EXPECT_NEAR(g.originY, 90.0, 1e-4);  // row 0 is the north edge

    const std::vector<float> all = readAll(*reader);
    const auto stats = statsOf(all);
    EXPECT_EQ(stats.nanCount, 0U);
    EXPECT_NEAR(stats.min, -9027.0, 1.0);
    EXPECT_NEAR(stats.max, 6229.0, 1.0);
    // Row 0 is the Arctic Ocean, the last rows the Antarctic ice sheet.
    const auto rowMean = [&](std::int64_t row) {
        const float* begin = all.data() + row * info.width;
        return std::accumulate(begin, begin + info.width, 0.0) / static_cast<double>(info.width);
    };
    EXPECT_LT(rowMean(0), 0.0);
    EXPECT_GT(rowMean(info.height - 1), 2000.0);
    EXPECT_GT(rowMean(info.height - 3), 2000.0);
    test::expectRandomWindowsMatch(*reader, all);
}

TEST(DemReaderRealData, LuxembourgTinyGeoTiff) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "luxembourg_elev_30s.tif");
    auto reader = mustOpen(path.string());
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.width, 95);
    EXPECT_EQ(info.height, 90);
    EXPECT_EQ(info.sampleType, "int16");
    ASSERT_TRUE(info.noDataValue.has_value());
    EXPECT_EQ(*info.noDataValue, -32768.0);
    const Georeference& g = info.georeference;
    EXPECT_EQ(g.crsKind, CrsKind::Geographic);
    EXPECT_EQ(g.epsg, 4326);
    EXPECT_NEAR(g.originX, 5.741667, 1e-6);
    EXPECT_NEAR(g.originY, 50.191667, 1e-6);
    EXPECT_NEAR(g.pixelSizeX, 0.0083333, 1e-7);

    const std::vector<float> all = readAll(*reader, 7);
    const auto stats = statsOf(all);
    EXPECT_GT(stats.nanCount, 0U);  // outside the border
    EXPECT_EQ(stats.min, 141.0F);
    EXPECT_EQ(stats.max, 547.0F);
    test::expectRandomWindowsMatch(*reader, all, 30);
}

TEST(DemReaderRealData, PugetSoundJpegTakesChannelZero) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "puget_sound_4k_8bit.jpg");
    auto reader = mustOpen(path.string());
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.width, 4096);
    EXPECT_EQ(info.height, 4096);
    EXPECT_EQ(info.sampleType, "uint8");
    const std::vector<float> all = readAll(*reader);
    const auto stats = statsOf(all);
    EXPECT_EQ(stats.nanCount, 0U);
    EXPECT_EQ(stats.min, 0.0F);
    EXPECT_EQ(stats.max, 171.0F);
    test::expectRandomWindowsMatch(*reader, all, 20);
}

// ---------------------------------------------------------------------------------------
// Rasters written here: every layout and sample type of the OpenImageIO and GDAL readers

class DemReaderWritten : public ::testing::Test {
protected:
    void SetUp() override {
        GDALAllRegister();
        ProceduralTerrainParameters p;
        p.widthSamples = 613;
        p.heightSamples = 389;
        Result<ProceduralTerrain> t = ProceduralTerrain::create(p);
        ASSERT_TRUE(t.ok());
        m_heights.resize(static_cast<std::size_t>(m_width * m_height));
        t.value().fillWindow(0, 0, m_width, m_height, m_heights);
    }

    // A GDAL-written GeoTIFF of the heights in `type` (rounded for integers), with
    // creation options such as TILED=YES.
    // The grid the writer places the heights on; without a CRS only the spacing is said.
    double m_spacing = 10.0;
    bool m_writeCrs = true;

    std::string writeWithGdal(const std::string& name, GDALDataType type,
                              std::vector<std::string> creationOptions,
                              std::optional<double> noData = std::nullopt,
                              const char* driverName = "GTiff") {
        const std::string path = m_dir.file(name);
        GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driverName);
        EXPECT_NE(driver, nullptr);
        if (driver == nullptr) return path;
        std::vector<char*> options;
        for (std::string& o : creationOptions) options.push_back(o.data());
        options.push_back(nullptr);
        GDALDataset* ds = driver->Create(path.c_str(), static_cast<int>(m_width),
                                         static_cast<int>(m_height), 1, type, options.data());
        EXPECT_NE(ds, nullptr);
        if (ds == nullptr) return path;
        std::array<double, 6> gt = {500000.0, m_spacing, 0.0, 5200000.0, 0.0, -m_spacing};
        ds->SetGeoTransform(gt.data());
        OGRSpatialReference srs;
        srs.importFromEPSG(32610);
        if (m_writeCrs) ds->SetSpatialRef(&srs);
        if (noData) ds->GetRasterBand(1)->SetNoDataValue(*noData);
        std::vector<double> values(m_heights.begin(), m_heights.end());
        if (type != GDT_Float32 && type != GDT_Float64)
            for (double& v : values) v = std::round(v / 8.0);  // fits int8/uint8 too
        EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(
                      GF_Write, 0, 0, static_cast<int>(m_width), static_cast<int>(m_height),
                      values.data(), static_cast<int>(m_width), static_cast<int>(m_height),
                      GDT_Float64, 0, 0, nullptr),
                  CE_None);
        GDALClose(ds);
        return path;
    }

    // What GDAL reads from `path` as floats (the reference for our readers).
    std::vector<float> readWithGdal(const std::string& path) {
        std::vector<float> values(static_cast<std::size_t>(m_width * m_height));
        GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
        EXPECT_NE(ds, nullptr);
        if (ds == nullptr) return values;
        EXPECT_EQ(
            ds->GetRasterBand(1)->RasterIO(
                GF_Read, 0, 0, static_cast<int>(m_width), static_cast<int>(m_height), values.data(),
                static_cast<int>(m_width), static_cast<int>(m_height), GDT_Float32, 0, 0, nullptr),
            CE_None);
        GDALClose(ds);
        return values;
    }

    TempDir m_dir;
    std::int64_t m_width = 613;
    std::int64_t m_height = 389;
    std::vector<float> m_heights;
};

TEST_F(DemReaderWritten, GeoTiffLayoutsAndTypesReadAsGdalReadsThem) {
    struct Case {
        const char* name;
        GDALDataType type;
        std::vector<std::string> options;
        const char* sampleType;
    };
    const std::vector<Case> cases = {
        {"int16_striped.tif", GDT_Int16, {}, "int16"},
        {"int16_strips_of_5.tif", GDT_Int16, {"BLOCKYSIZE=5", "COMPRESS=DEFLATE"}, "int16"},
        {"uint16_tiled.tif",
         GDT_UInt16,
         {"TILED=YES", "BLOCKXSIZE=128", "BLOCKYSIZE=64"},
         "uint16"},
        {"float32_tiled_lzw.tif",
         GDT_Float32,
         {"TILED=YES", "COMPRESS=LZW", "PREDICTOR=3"},
         "float32"},
        {"float64_striped.tif", GDT_Float64, {}, "float64"},
        {"float32_bigtiff.tif", GDT_Float32, {"TILED=YES", "BIGTIFF=YES"}, "float32"},
        {"uint8_whole_strip.tif", GDT_Byte, {"BLOCKYSIZE=389"}, "uint8"},
        {"int32_tiled.tif", GDT_Int32, {"TILED=YES"}, "int32"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string path = writeWithGdal(c.name, c.type, c.options);
        auto reader = mustOpen(path);
        ASSERT_TRUE(reader);
        const DemInfo& info = reader->info();
        EXPECT_EQ(info.readerName, "oiio");
        EXPECT_EQ(info.sampleType, c.sampleType);
        EXPECT_EQ(info.width, m_width);
        EXPECT_EQ(info.height, m_height);
        EXPECT_TRUE(info.hasGeoreference);
        EXPECT_EQ(info.georeference.crsKind, CrsKind::Projected);
        EXPECT_EQ(info.georeference.epsg, 32610);
        EXPECT_EQ(info.georeference.originX, 500000.0);
        EXPECT_EQ(info.georeference.originY, 5200000.0);
        EXPECT_EQ(info.georeference.pixelSizeX, 10.0);
        const std::vector<float> all = readAll(*reader, 37);
        EXPECT_EQ(countDifferences(all, readWithGdal(path)), 0U);
        test::expectRandomWindowsMatch(*reader, all, 15);
    }
}

TEST_F(DemReaderWritten, GdalNoDataTagBecomesNaN) {
    const double noData = std::round(m_heights[1000] / 8.0);  // a value that occurs
    const std::string path = writeWithGdal("nodata.tif", GDT_Int16, {"TILED=YES"}, noData);
    auto reader = mustOpen(path);
    ASSERT_TRUE(reader);
    ASSERT_TRUE(reader->info().noDataValue.has_value());
    EXPECT_EQ(*reader->info().noDataValue, noData);
    const std::vector<float> all = readAll(*reader);
    const std::vector<float> gdal = readWithGdal(path);
    std::size_t expectedNaN = 0;
    for (const float v : gdal) expectedNaN += v == static_cast<float>(noData) ? 1 : 0;
    ASSERT_GT(expectedNaN, 0U);
    EXPECT_EQ(statsOf(all).nanCount, expectedNaN);
}

TEST_F(DemReaderWritten, GdalScaleAndOffsetApply) {
    // GDAL keeps them in the GDAL_METADATA tag of a GeoTIFF, in band attributes elsewhere.
    for (const char* name : {"scaled.tif", "scaled.img"}) {
        SCOPED_TRACE(name);
        const std::string path =
            writeWithGdal(name, GDT_Int16, {}, std::nullopt,
                          std::string(name).ends_with(".tif") ? "GTiff" : "HFA");
        GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE);
        ASSERT_NE(ds, nullptr);
        ds->GetRasterBand(1)->SetScale(0.25);
        ds->GetRasterBand(1)->SetOffset(-7.0);
        GDALClose(ds);
        auto reader = mustOpen(path);
        ASSERT_TRUE(reader);
        EXPECT_EQ(reader->info().vertical, (VerticalTransform{0.25, -7.0}));
        const std::vector<float> all = readAll(*reader);
        const std::vector<float> raw = readWithGdal(path);
        for (std::size_t i = 0; i < all.size(); i += 53) ASSERT_EQ(all[i], raw[i] * 0.25F - 7.0F);
    }
}

TEST_F(DemReaderWritten, HeightImageWriterFilesRoundTrip) {
    HeightImageOptions options;
    options.georeference = Georeference{1500.0, 30000.0, 30.0, 30.0, 32633};
    for (const char* name : {"deflate.tif", "plain.tif", "big.tif", "heights.exr"}) {
        SCOPED_TRACE(name);
        const std::string path = m_dir.file(name);
        HeightImageOptions o = options;
        if (std::string(name) == "plain.tif") o.tiffCompression = TiffCompression::None;
        if (std::string(name) == "big.tif") o.bigTiff = BigTiffMode::Always;
        const auto written = writeHeightImage(path, m_width, m_height, m_heights, o);
        ASSERT_TRUE(written.ok()) << written.error().message;
        auto reader = mustOpen(path);
        ASSERT_TRUE(reader);
        EXPECT_EQ(reader->info().sampleType, "float32");
        if (std::string(name).ends_with(".tif")) {
            EXPECT_TRUE(reader->info().hasGeoreference);
            EXPECT_EQ(reader->info().georeference, *options.georeference);
        }
        const std::vector<float> all = readAll(*reader, 131);
        EXPECT_EQ(countDifferences(all, m_heights), 0U);
        test::expectRandomWindowsMatch(*reader, all, 15);
    }
}

TEST_F(DemReaderWritten, Png16WithScaleAndOffset) {
    const std::string path = m_dir.file("heights.png");
    HeightImageOptions o;
    o.pngScaleM = 0.1;
    o.pngOffsetM = -100.0;
    ASSERT_TRUE(writeHeightImage(path, m_width, m_height, m_heights, o).ok());
    DemOpenOptions options;
    options.verticalScale = 0.1;
    options.verticalOffset = -100.0;
    auto reader = mustOpen(path, options);
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->info().sampleType, "uint16");
    const std::vector<float> all = readAll(*reader);
    for (std::size_t i = 0; i < all.size(); i += 97) EXPECT_NEAR(all[i], m_heights[i], 0.051);
}

TEST_F(DemReaderWritten, HalfFloatExr) {
    // OpenImageIO writes half when asked; the reader widens it.
    const std::string path = m_dir.file("half.exr");
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(static_cast<int>(m_width), static_cast<int>(m_height), 1,
                         OIIO::TypeDesc::HALF);
    spec.tile_width = spec.tile_height = 64;
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, m_heights.data()));
    ASSERT_TRUE(out->close());
    auto reader = mustOpen(path);
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->info().sampleType, "float16");
    const std::vector<float> all = readAll(*reader);
    for (std::size_t i = 0; i < all.size(); i += 89)
        EXPECT_NEAR(all[i], m_heights[i], std::abs(m_heights[i]) * 1e-3 + 1e-3);
    test::expectRandomWindowsMatch(*reader, all, 10);
}

TEST_F(DemReaderWritten, GdalFormatsAndRowsRunningNorth) {
    // ERDAS Imagine through GDAL, and a VRT over it whose geotransform runs north (rows
    // stored south first): our row 0 must be its last row.
    const std::string img = writeWithGdal("heights.img", GDT_Float32, {}, std::nullopt, "HFA");
    auto reader = mustOpen(img);
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->info().readerName, "gdal");
    EXPECT_EQ(reader->info().georeference.epsg, 32610);
    const std::vector<float> all = readAll(*reader);
    EXPECT_EQ(countDifferences(all, m_heights), 0U);

    const std::string vrt = m_dir.file("south_up.vrt");
    {
        std::ofstream out(vrt);
        out << "<VRTDataset rasterXSize=\"" << m_width << "\" rasterYSize=\"" << m_height << "\">\n"
            << "  <GeoTransform>100, 2, 0, 1000, 0, 2</GeoTransform>\n"
            << "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
            << "    <SimpleSource><SourceFilename relativeToVRT=\"1\">heights.img</SourceFilename>"
            << "<SourceBand>1</SourceBand></SimpleSource>\n"
            << "  </VRTRasterBand>\n</VRTDataset>\n";
    }
    auto flipped = mustOpen(vrt);
    ASSERT_TRUE(flipped);
    EXPECT_EQ(flipped->info().georeference.originY, 1000.0 + 2.0 * static_cast<double>(m_height));
    EXPECT_EQ(flipped->info().georeference.pixelSizeY, 2.0);
    const std::vector<float> north = readAll(*flipped, 50);
    for (std::int64_t y = 0; y < m_height; ++y)
        ASSERT_EQ(countDifferences(north.data() + y * m_width,
                                   m_heights.data() + (m_height - 1 - y) * m_width,
                                   static_cast<std::size_t>(m_width)),
                  0U)
            << "row " << y;
    test::expectRandomWindowsMatch(*flipped, north, 15);
}

TEST_F(DemReaderWritten, HgtTileFromItsName) {
    // S12W077.hgt: SW corner 12 S, 77 W; 3601² = 1" samples; a few voids.
    const std::int64_t side = 3601;
    std::vector<char> bytes(static_cast<std::size_t>(side * side * 2));
    for (std::int64_t i = 0; i < side * side; ++i) {
        auto v = static_cast<std::uint16_t>(static_cast<std::int16_t>((i % 3000) - 500));
        if (i % 100003 == 0) v = 0x8000;  // -32768
        bytes[static_cast<std::size_t>(2 * i)] = static_cast<char>(v >> 8U);
        bytes[static_cast<std::size_t>(2 * i + 1)] = static_cast<char>(v & 0xFFU);
    }
    const std::string path = m_dir.file("S12W077.hgt");
    test::writeBytes(path, bytes);
    auto reader = mustOpen(path);
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.width, side);
    const double step = 1.0 / 3600.0;
    EXPECT_DOUBLE_EQ(info.georeference.originX, -77.0 - 0.5 * step);
    EXPECT_DOUBLE_EQ(info.georeference.originY, -11.0 + 0.5 * step);
    EXPECT_DOUBLE_EQ(info.georeference.pixelSizeY, step);
    std::vector<float> row(static_cast<std::size_t>(side));
    ASSERT_TRUE(reader->readWindow(0, 1, side, 1, row).ok());
    EXPECT_EQ(row[0], static_cast<float>((side % 3000) - 500));
    const std::vector<float> all = readAll(*reader, 400);
    EXPECT_EQ(statsOf(all).nanCount, static_cast<std::size_t>((side * side - 1) / 100003 + 1));

    // A name that says no place: no georeference, unless the options give one.
    const std::string unnamed = m_dir.file("tile.hgt");
    fs::copy_file(path, unnamed);
    auto plain = mustOpen(unnamed);
    ASSERT_TRUE(plain);
    EXPECT_FALSE(plain->info().hasGeoreference);
    EXPECT_EQ(plain->info().georeference.crsKind, CrsKind::Unknown);
}

// A grid spacing without a CRS (a GeoTIFF with ModelPixelScale and no GeoKeys, an ESRI
// .bil/.hdr without .prj) is built at that spacing in metres, as GDAL shows it, and says
// so; before, the builder took it as 1 m and drew a needle forest. The spacing below is
// the held-out polar grid's: 5,000 m.
TEST_F(DemReaderWritten, SpacingWithoutCrsIsMetresWithAWarning) {
    m_writeCrs = false;
    m_spacing = 5000.0;
    for (const auto& [name, driver, readerName] :
         {std::tuple{"no-crs.tif", "GTiff", "oiio"}, std::tuple{"no-crs.bil", "EHdr", "gdal"}}) {
        SCOPED_TRACE(name);
        const std::string path = writeWithGdal(name, GDT_Float32, {}, std::nullopt, driver);
        auto reader = mustOpen(path);
        ASSERT_TRUE(reader);
        const DemInfo& info = reader->info();
        EXPECT_EQ(info.readerName, readerName);
        EXPECT_TRUE(info.hasGeoreference);
        EXPECT_EQ(info.georeference.crsKind, CrsKind::Projected);
        EXPECT_EQ(info.georeference.epsg, Georeference::kUnknownProjectedCrs);
        EXPECT_EQ(info.georeference.pixelSizeX, 5000.0);
        EXPECT_EQ(info.georeference.pixelSizeY, 5000.0);
        EXPECT_EQ(info.georeference.originX, 500000.0);
        ASSERT_EQ(info.warnings.size(), 1U);
        EXPECT_TRUE(info.warnings[0].starts_with(path)) << info.warnings[0];
        EXPECT_NE(info.warnings[0].find("CRS is unknown"), std::string::npos) << info.warnings[0];
        EXPECT_NE(info.warnings[0].find("5000 × 5000"), std::string::npos) << info.warnings[0];
        EXPECT_NE(info.warnings[0].find("--epsg"), std::string::npos) << info.warnings[0];

        // Saying the CRS silences it; a file with its CRS never had one.
        DemOpenOptions named;
        named.epsg = 3413;
        auto placed = mustOpen(path, named);
        ASSERT_TRUE(placed);
        EXPECT_EQ(placed->info().georeference.crsKind, CrsKind::Projected);
        EXPECT_EQ(placed->info().georeference.epsg, 3413);
        EXPECT_TRUE(placed->info().warnings.empty());
    }
    m_writeCrs = true;
    auto withCrs = mustOpen(writeWithGdal("crs.tif", GDT_Float32, {}));
    ASSERT_TRUE(withCrs);
    EXPECT_TRUE(withCrs->info().warnings.empty());
}

// ---------------------------------------------------------------------------------------
// Options and the procedural source

TEST_F(DemReaderWritten, OptionsOverrideTheFile) {
    const std::string path = writeWithGdal("over.tif", GDT_Int16, {"TILED=YES"});
    DemOpenOptions options;
    options.pixelSize = 0.1;  // degrees: 613 × 389 samples from 60° N reach 21.1° N
    options.originX = -10.0;
    options.originY = 60.0;
    options.epsg = 4326;
    options.verticalScale = 2.0;
    options.verticalOffset = 1.0;
    options.noDataValue = 0.0;
    auto reader = mustOpen(path, options);
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.georeference.crsKind, CrsKind::Geographic);
    EXPECT_EQ(info.georeference.epsg, 4326);
    EXPECT_NE(info.georeference.wkt.find("WGS 84"), std::string::npos);
    EXPECT_EQ(info.georeference.pixelSizeX, 0.1);
    EXPECT_EQ(info.georeference.pixelSizeY, 0.1);
    EXPECT_EQ(info.georeference.originX, -10.0);
    EXPECT_EQ(info.georeference.originY, 60.0);
    const std::vector<float> all = readAll(*reader);
    const std::vector<float> raw = readWithGdal(path);
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (raw[i] == 0.0F)
            ASSERT_TRUE(std::isnan(all[i])) << i;
        else
            ASSERT_EQ(all[i], raw[i] * 2.0F + 1.0F) << i;
    }

    // Degrees that carry the grid past a pole are refused, naming the file (0.5° from 60° N
    // reaches 134.5° S).
    DemOpenOptions beyondThePole = options;
    beyondThePole.pixelSize = 0.5;
    auto refused = openOne(path, beyondThePole);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("over.tif: placed by --spacing/--origin"),
              std::string::npos)
        << refused.error().message;
    EXPECT_NE(refused.error().message.find("beyond the globe"), std::string::npos);

    // A placement for a raster that has none is projected metres, unless an EPSG says.
    const std::string png = m_dir.file("plain.png");
    ASSERT_TRUE(writeHeightImage(png, m_width, m_height, m_heights).ok());
    DemOpenOptions spacing;
    spacing.pixelSize = 160.0;
    auto placed = mustOpen(png, spacing);
    ASSERT_TRUE(placed);
    EXPECT_TRUE(placed->info().hasGeoreference);
    EXPECT_EQ(placed->info().georeference.crsKind, CrsKind::Projected);
    EXPECT_EQ(placed->info().georeference.pixelSizeX, 160.0);

    DemOpenOptions badEpsg;
    badEpsg.epsg = 999999;
    const auto bad = openOne(png, badEpsg);
    ASSERT_FALSE(bad.ok());
    EXPECT_TRUE(bad.error().message.starts_with(png)) << bad.error().message;
    EXPECT_NE(bad.error().message.find("EPSG:999999"), std::string::npos);
}

TEST(DemReaderProcedural, EqualsFillWindow) {
    const std::string spec = "procedural:size=1025,seed=7,spacing=10";
    auto reader = mustOpen(spec);
    ASSERT_TRUE(reader);
    const DemInfo& info = reader->info();
    EXPECT_EQ(info.readerName, "procedural");
    EXPECT_EQ(info.sampleType, "float32");
    EXPECT_EQ(info.width, 1025);
    EXPECT_EQ(info.height, 1025);
    EXPECT_EQ(info.inputs, std::vector<std::string>{spec});
    ProceduralTerrainParameters p;
    p.widthSamples = p.heightSamples = 1025;
    p.seed = 7;
    p.sampleSpacingM = 10.0;
    Result<ProceduralTerrain> terrain = ProceduralTerrain::create(p);
    ASSERT_TRUE(terrain.ok());
    EXPECT_TRUE(info.hasGeoreference);
    EXPECT_EQ(info.georeference, terrain.value().windowGeoreference(0, 0));
    std::vector<float> expected(1025 * 1025);
    terrain.value().fillWindow(0, 0, 1025, 1025, expected);
    const std::vector<float> all = readAll(*reader);
    EXPECT_EQ(countDifferences(all, expected), 0U);
    test::expectRandomWindowsMatch(*reader, all, 10);

    auto rectangle = mustOpen("procedural:width=300,height=200");
    ASSERT_TRUE(rectangle);
    EXPECT_EQ(rectangle->info().width, 300);
    EXPECT_EQ(rectangle->info().height, 200);
    auto defaults = mustOpen("procedural:");
    ASSERT_TRUE(defaults);
    EXPECT_EQ(defaults->info().width, ProceduralTerrainParameters{}.widthSamples);
}

TEST(DemReaderProceduralDeathTest, WindowOutsideTheRasterIsAProgrammerError) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");  // earlier tests leave library threads
    auto reader = mustOpen("procedural:size=65");
    ASSERT_TRUE(reader);
    std::vector<float> out(4);
    EXPECT_DEATH((void)reader->readWindow(64, 0, 2, 2, out), "outside the raster");
    EXPECT_DEATH((void)reader->readWindow(0, 0, 4, 4, out), "smaller than the window");
}

TEST(DemReaderProcedural, BadSpecsAreErrors) {
    for (const std::string spec :
         {"procedural:size=abc", "procedural:colour=red", "procedural:size", "procedural:size=3",
          "procedural:spacing=-1", "procedural:seed=1.5"}) {
        const auto reader = openOne(spec);
        ASSERT_FALSE(reader.ok()) << spec;
        EXPECT_TRUE(reader.error().message.starts_with(spec)) << reader.error().message;
    }
}

// Height units from the file (netCDF/CF `units`, after scale_factor and add_offset): a grid
// stored in km, or in feet, reads as metres; a unit that is no length is refused by name.
TEST_F(DemReaderWritten, NetCdfHeightUnitsAreHonoured) {
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDriver* netcdf = GetGDALDriverManager()->GetDriverByName("netCDF");
    ASSERT_NE(mem, nullptr);
    ASSERT_NE(netcdf, nullptr) << "GDAL without its netCDF driver";
    const auto write = [&](const std::string& name, const char* unit, double scale, double offset) {
        GDALDataset* ds = mem->Create("", 4, 3, 1, GDT_Float32, nullptr);
        std::array<double, 6> gt = {10.0, 0.5, 0.0, 50.0, 0.0, -0.5};
        ds->SetGeoTransform(gt.data());
        OGRSpatialReference srs;
        srs.importFromEPSG(4326);
        ds->SetSpatialRef(&srs);
        GDALRasterBand* band = ds->GetRasterBand(1);
        band->SetUnitType(unit);
        band->SetMetadataItem("units", unit);  // what the netCDF driver writes as CF `units`
        band->SetScale(scale);
        band->SetOffset(offset);
        std::vector<float> raw(12);
        std::iota(raw.begin(), raw.end(), 1.0f);  // 1 … 12 raw units
        EXPECT_EQ(
            band->RasterIO(GF_Write, 0, 0, 4, 3, raw.data(), 4, 3, GDT_Float32, 0, 0, nullptr),
            CE_None);
        const std::string path = m_dir.file(name);
        GDALDataset* copy = netcdf->CreateCopy(path.c_str(), ds, FALSE, nullptr, nullptr, nullptr);
        EXPECT_NE(copy, nullptr);
        if (copy != nullptr) GDALClose(copy);
        GDALClose(ds);
        return path;
    };
    const auto firstHeight = [&](const std::string& path) -> std::optional<float> {
        auto reader = openDem({path});
        if (!reader) {
            ADD_FAILURE() << reader.error().message;
            return std::nullopt;
        }
        std::vector<float> out(12);
        EXPECT_TRUE(reader.value()->readWindow(0, 0, 4, 3, out));
        return out[0];
    };
    // raw 1 · 0.5 + 0.25 = 0.75 km = 750 m
    EXPECT_FLOAT_EQ(firstHeight(write("km.nc", "km", 0.5, 0.25)).value_or(0.0f), 750.0f);
    EXPECT_FLOAT_EQ(firstHeight(write("ft.nc", "ft", 1.0, 0.0)).value_or(0.0f), 0.3048f);
    EXPECT_FLOAT_EQ(firstHeight(write("m.nc", "m", 1.0, 0.0)).value_or(0.0f), 1.0f);
    const std::string celsius = write("celsius.nc", "degC", 1.0, 0.0);
    auto refused = openDem({celsius});
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find(celsius), std::string::npos) << refused.error().message;
    EXPECT_NE(refused.error().message.find("height unit \"degC\""), std::string::npos)
        << refused.error().message;
}

}  // namespace
}  // namespace terrain::io
