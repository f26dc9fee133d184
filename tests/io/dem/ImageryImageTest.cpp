// openImageryImage (issue 47): every colour layout GDAL gives as RGBA8 (RGB, grey, palette,
// alpha, no-data), terrain points placed on the image through its CRS, and the refusals that
// name the file: 16-bit bands, no georeference, a CRS PROJ cannot transform, a truncated file.
#include "TempFolder.h"

#include "terrain/dem/OpenImageryImage.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

namespace terrain::io {
namespace {

constexpr int kW = 64, kH = 32;
// Whole degrees: 0.5° pixels from 10°E, 50°N.
constexpr std::array<double, 6> kGeographic = {10.0, 0.5, 0.0, 50.0, 0.0, -0.5};

class ImageryImageTest : public ::testing::Test {
protected:
    void SetUp() override { GDALAllRegister(); }

    // A GeoTIFF of `bands` bands of `type`; band b's pixel (x, y) is value(b, x, y).
    std::string write(const std::string& name, int bands, GDALDataType type,
                      const std::function<double(int, int, int)>& value, bool georeferenced = true,
                      const char* wkt = nullptr) {
        GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
        GDALDataset* ds = mem->Create("", kW, kH, bands, type, nullptr);
        if (georeferenced) {
            std::array<double, 6> gt = kGeographic;
            ds->SetGeoTransform(gt.data());
            OGRSpatialReference srs;
            if (wkt)
                srs.importFromWkt(wkt);
            else
                srs.importFromEPSG(4326);
            ds->SetSpatialRef(&srs);
        }
        for (int b = 1; b <= bands; ++b) {
            std::vector<double> v;
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) v.push_back(value(b, x, y));
            EXPECT_EQ(ds->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, kW, kH, v.data(), kW, kH,
                                                     GDT_Float64, 0, 0, nullptr),
                      CE_None);
        }
        if (m_configure) m_configure(ds);
        m_configure = nullptr;
        const std::string path = m_dir.file(name);
        GDALDataset* copy = GetGDALDriverManager()->GetDriverByName("GTiff")->CreateCopy(
            path.c_str(), ds, FALSE, nullptr, nullptr, nullptr);
        EXPECT_NE(copy, nullptr);
        GDALClose(copy);
        GDALClose(ds);
        return path;
    }

    static ImageryPlacement globe() {
        ImageryPlacement p;
        p.globe = true;
        return p;
    }

    static std::array<std::uint8_t, 4> pixel(ImageryImage& image, int x, int y, int k = 0) {
        std::array<std::uint8_t, 4> out{};
        const Status s = image.readBlocks(x, y, 1, 1, k, out);
        EXPECT_TRUE(s.ok()) << s.error().message;
        return out;
    }

    test::TempFolder m_dir;
    std::function<void(GDALDataset*)> m_configure;
};

TEST_F(ImageryImageTest, RgbIsPlacedThroughItsGeoreference) {
    const std::string path = write("rgb.tif", 3, GDT_Byte, [](int b, int x, int y) {
        return b == 1 ? x * 2 : b == 2 ? y * 4 : 7;
    });
    auto image = openImageryImage(path, globe());
    ASSERT_TRUE(image.ok()) << image.error().message;
    ImageryImage& i = *image.value();
    EXPECT_EQ(i.width(), kW);
    EXPECT_FALSE(i.wrapsColumns());
    std::vector<double> xs = {10.25, 20.0}, ys = {49.75, 45.0};
    i.toPixels(xs, ys);
    EXPECT_NEAR(xs[0], 0.5, 1e-9);
    EXPECT_NEAR(ys[0], 0.5, 1e-9);
    EXPECT_NEAR(xs[1], 20.0, 1e-9);
    EXPECT_NEAR(ys[1], 10.0, 1e-9);
    const auto back = i.toTerrain(20.0, 10.0);
    EXPECT_NEAR(back[0], 20.0, 1e-9);
    EXPECT_NEAR(back[1], 45.0, 1e-9);
    EXPECT_EQ(pixel(i, 5, 3), (std::array<std::uint8_t, 4>{10, 12, 7, 255}));
    // 2 × 2 blocks: block (2, 1) averages x 4…5, y 2…3.
    EXPECT_EQ(pixel(i, 2, 1, 1), (std::array<std::uint8_t, 4>{9, 10, 7, 255}));
}

TEST_F(ImageryImageTest, GreyPaletteAlphaAndNoDataBecomeRgba) {
    auto grey = openImageryImage(write("grey.tif", 1, GDT_Byte, [](int, int x, int) { return x; }),
                                 globe());
    ASSERT_TRUE(grey.ok()) << grey.error().message;
    EXPECT_EQ(pixel(*grey.value(), 9, 0), (std::array<std::uint8_t, 4>{9, 9, 9, 255}));

    m_configure = [](GDALDataset* ds) {
        GDALColorTable table;
        for (int i = 0; i < 4; ++i) {
            const GDALColorEntry e{static_cast<short>(i * 60), static_cast<short>(200 - i),
                                   static_cast<short>(i), static_cast<short>(i == 3 ? 0 : 255)};
            table.SetColorEntry(i, &e);
        }
        ds->GetRasterBand(1)->SetColorInterpretation(GCI_PaletteIndex);
        ds->GetRasterBand(1)->SetColorTable(&table);
    };
    auto palette = openImageryImage(
        write("palette.tif", 1, GDT_Byte, [](int, int x, int) { return x % 4; }), globe());
    ASSERT_TRUE(palette.ok()) << palette.error().message;
    EXPECT_EQ(pixel(*palette.value(), 2, 0), (std::array<std::uint8_t, 4>{120, 198, 2, 255}));
    // (TIFF colour maps have no alpha: entry 3's 0 is not stored.)
    EXPECT_EQ(pixel(*palette.value(), 3, 0), (std::array<std::uint8_t, 4>{180, 197, 3, 255}));

    m_configure = [](GDALDataset* ds) {
        ds->GetRasterBand(4)->SetColorInterpretation(GCI_AlphaBand);
    };
    auto rgba = openImageryImage(
        write("rgba.tif", 4, GDT_Byte, [](int b, int x, int) { return b == 4 ? x * 3 : 50; }),
        globe());
    ASSERT_TRUE(rgba.ok()) << rgba.error().message;
    EXPECT_EQ(pixel(*rgba.value(), 10, 0), (std::array<std::uint8_t, 4>{50, 50, 50, 30}));

    m_configure = [](GDALDataset* ds) {
        for (int b = 1; b <= 3; ++b) ds->GetRasterBand(b)->SetNoDataValue(0.0);
    };
    auto noData = openImageryImage(
        write("nodata.tif", 3, GDT_Byte, [](int, int x, int) { return x < 8 ? 0 : 100; }), globe());
    ASSERT_TRUE(noData.ok()) << noData.error().message;
    EXPECT_EQ(pixel(*noData.value(), 3, 0)[3], 0);
    EXPECT_EQ(pixel(*noData.value(), 9, 0), (std::array<std::uint8_t, 4>{100, 100, 100, 255}));
}

TEST_F(ImageryImageTest, SixteenBitBandsAreRefusedAsProbablyADem) {
    const std::string path =
        write("dem.tif", 1, GDT_Int16, [](int, int x, int y) { return 1000 + x + y; });
    const auto refused = openImageryImage(path, globe());
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find(path), std::string::npos);
    EXPECT_NE(refused.error().message.find("Int16"), std::string::npos);
    EXPECT_NE(refused.error().message.find("probably a DEM"), std::string::npos);
    EXPECT_NE(refused.error().message.find("gdal_translate -ot Byte -scale"), std::string::npos);
}

TEST_F(ImageryImageTest, WithoutGeoreferenceOnlyOnTheDemExtent) {
    const std::string path = write(
        "plain.tif", 3, GDT_Byte, [](int, int x, int) { return x; }, false);
    const auto refused = openImageryImage(path, globe());
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("no georeference"), std::string::npos);
    EXPECT_NE(refused.error().message.find(path), std::string::npos);
    ImageryPlacement plane;
    plane.rasterWidth = 129;
    plane.rasterHeight = 65;
    plane.demExtent = true;
    auto image = openImageryImage(path, plane);
    ASSERT_TRUE(image.ok()) << image.error().message;
    // The image's outer edges on the first and last samples.
    std::vector<double> xs = {0.0, 128.0}, ys = {0.0, 64.0};
    image.value()->toPixels(xs, ys);
    EXPECT_DOUBLE_EQ(xs[0], 0.0);
    EXPECT_DOUBLE_EQ(ys[0], 0.0);
    EXPECT_DOUBLE_EQ(xs[1], kW);
    EXPECT_DOUBLE_EQ(ys[1], kH);
}

TEST_F(ImageryImageTest, ACrsProjCannotTransformIsRefused) {
    const char* engineering = R"(LOCAL_CS["a site grid",LOCAL_DATUM["site",32767],UNIT["metre",1],)"
                              R"(AXIS["Easting",EAST],AXIS["Northing",NORTH]])";
    const std::string path = write(
        "local.tif", 3, GDT_Byte, [](int, int, int) { return 1; }, true, engineering);
    const auto refused = openImageryImage(path, globe());
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find(path), std::string::npos);
    EXPECT_NE(refused.error().message.find("PROJ cannot transform"), std::string::npos)
        << refused.error().message;
}

TEST_F(ImageryImageTest, ATruncatedFileIsAnErrorNamingIt) {
    const std::string path = write("cut.tif", 3, GDT_Byte, [](int b, int x, int y) {
        return (b * 31 + x * 7 + y * 13) % 256;
    });
    std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
    // Refused at open, though the blocks before the cut would read.
    const auto image = openImageryImage(path, globe());
    ASSERT_FALSE(image.ok());
    EXPECT_NE(image.error().message.find(path), std::string::npos);
    EXPECT_NE(image.error().message.find("truncated"), std::string::npos) << image.error().message;
}

TEST_F(ImageryImageTest, MissingFileAndWholeEarthWrap) {
    const auto missing = openImageryImage(m_dir.file("none.tif"), globe());
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("none.tif"), std::string::npos);
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDataset* ds = mem->Create("", 360, 180, 3, GDT_Byte, nullptr);
    std::array<double, 6> gt = {-180.0, 1.0, 0.0, 90.0, 0.0, -1.0};
    ds->SetGeoTransform(gt.data());
    OGRSpatialReference srs;
    srs.importFromEPSG(4326);
    ds->SetSpatialRef(&srs);
    const std::string path = m_dir.file("world.tif");
    GDALClose(GetGDALDriverManager()->GetDriverByName("GTiff")->CreateCopy(
        path.c_str(), ds, FALSE, nullptr, nullptr, nullptr));
    GDALClose(ds);
    auto world = openImageryImage(path, globe());
    ASSERT_TRUE(world.ok()) << world.error().message;
    EXPECT_TRUE(world.value()->wrapsColumns());
}

}  // namespace
}  // namespace terrain::io
