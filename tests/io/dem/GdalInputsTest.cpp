// Inputs the GDAL way (issue 21): a band chosen with -b, several bands warned about, a
// container's subdatasets listed and opened by GDAL's name for them, an inline VRT, grids
// whose rows run north or columns west read north-up with their heights where GDAL puts
// them, and rotated and sheared grids resampled north-up by GDAL's warper. Every file is
// written here with GDAL's own API.
#include "DemTestSupport.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

using test::readAll;
using test::TempDir;

constexpr int kWidth = 5;
constexpr int kHeight = 4;

// Band b's sample at column x, row y (as stored in the file): distinct everywhere, each
// band above the one before, all within a byte.
float storedValue(int band, int x, int y) { return static_cast<float>(50 * band + 10 * y + x); }

DemOpenOptions bandOption(int band) {
    DemOpenOptions options;
    options.band = band;
    return options;
}

class GdalInputsTest : public ::testing::Test {
protected:
    void SetUp() override { GDALAllRegister(); }

    // A MEM dataset of `bands` float bands of storedValue, placed by `geoTransform`.
    static GDALDataset* memoryDataset(int bands, const std::array<double, 6>& geoTransform,
                                      GDALDataType type = GDT_Float32) {
        GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
        GDALDataset* ds = mem->Create("", kWidth, kHeight, bands, type, nullptr);
        std::array<double, 6> gt = geoTransform;
        ds->SetGeoTransform(gt.data());
        OGRSpatialReference srs;
        srs.importFromEPSG(32610);
        ds->SetSpatialRef(&srs);
        for (int b = 1; b <= bands; ++b) {
            std::vector<float> values;
            for (int y = 0; y < kHeight; ++y)
                for (int x = 0; x < kWidth; ++x) values.push_back(storedValue(b, x, y));
            EXPECT_EQ(ds->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, kWidth, kHeight, values.data(),
                                                     kWidth, kHeight, GDT_Float32, 0, 0, nullptr),
                      CE_None);
        }
        return ds;
    }

    std::string copyTo(GDALDataset* source, const char* driverName, const std::string& name) {
        const std::string path = m_dir.file(name);
        GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driverName);
        EXPECT_NE(driver, nullptr) << driverName;
        GDALDataset* copy =
            driver->CreateCopy(path.c_str(), source, FALSE, nullptr, nullptr, nullptr);
        EXPECT_NE(copy, nullptr) << path;
        if (copy != nullptr) GDALClose(copy);
        GDALClose(source);
        return path;
    }

    static constexpr std::array<double, 6> kNorthUp = {500000.0, 10.0, 0.0, 5200000.0, 0.0, -10.0};

    TempDir m_dir;
};

TEST_F(GdalInputsTest, BandIsChosenAndSeveralBandsAreWarnedAbout) {
    const std::string tiff = copyTo(memoryDataset(3, kNorthUp), "GTiff", "three-bands.tif");
    {
        auto reader = test::openOne(tiff);
        ASSERT_TRUE(reader) << reader.error().message;
        const DemInfo& info = reader.value()->info();
        EXPECT_EQ(info.readerName, "gdal");  // the OpenImageIO reader hands bands to GDAL
        EXPECT_EQ(info.band, 1);
        EXPECT_EQ(info.bandCount, 3);
        ASSERT_EQ(info.warnings.size(), 1u);
        EXPECT_NE(info.warnings.front().find("3 bands"), std::string::npos)
            << info.warnings.front();
        EXPECT_NE(info.warnings.front().find("-b/--band"), std::string::npos);
        EXPECT_EQ(readAll(*reader.value()).front(), storedValue(1, 0, 0));
    }
    {
        auto reader = test::openOne(tiff, bandOption(2));
        ASSERT_TRUE(reader) << reader.error().message;
        EXPECT_EQ(reader.value()->info().band, 2);
        EXPECT_TRUE(reader.value()->info().warnings.empty());
        const std::vector<float> all = readAll(*reader.value());
        EXPECT_EQ(all[static_cast<std::size_t>(kWidth + 3)], storedValue(2, 3, 1));
    }
    const auto missing = test::openOne(tiff, bandOption(4));
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("band 4 does not exist: bands are numbered 1 to 3"),
              std::string::npos)
        << missing.error().message;
    EXPECT_TRUE(missing.error().message.starts_with(tiff)) << missing.error().message;
    // Band 0 and negative bands the same way (GDAL numbers bands from 1).
    for (const int band : {0, -1}) {
        const auto none = test::openOne(tiff, bandOption(band));
        ASSERT_FALSE(none) << band;
        EXPECT_NE(none.error().message.find(tiff + ": band " + std::to_string(band) +
                                            " does not exist: bands are numbered 1 to 3"),
                  std::string::npos)
            << none.error().message;
    }

    // An RGB PNG: its channels are bands too.
    GDALDataset* bytes = memoryDataset(3, kNorthUp, GDT_Byte);
    const std::string png = copyTo(bytes, "PNG", "rgb.png");
    auto rgb = test::openOne(png, bandOption(3));
    ASSERT_TRUE(rgb) << rgb.error().message;
    EXPECT_EQ(readAll(*rgb.value()).back(), storedValue(3, kWidth - 1, kHeight - 1));

    // A single-band file takes -b 1 and refuses -b 2; so do the procedural source and .hgt.
    EXPECT_TRUE(
        test::openOne(copyTo(memoryDataset(1, kNorthUp), "GTiff", "one.tif"), bandOption(1)));
    const auto second = test::openOne(m_dir.file("one.tif"), bandOption(2));
    ASSERT_FALSE(second);
    EXPECT_NE(second.error().message.find("band 2 does not exist: it has one band, band 1"),
              std::string::npos)
        << second.error().message;
    EXPECT_FALSE(test::openOne("procedural:size=65", bandOption(2)));
}

TEST_F(GdalInputsTest, ContainerListsItsSubdatasetsAndOpensOneByName) {
    GDALDriver* netcdf = GetGDALDriverManager()->GetDriverByName("netCDF");
    ASSERT_NE(netcdf, nullptr) << "GDAL without its netCDF driver";
    const std::string path = m_dir.file("two-variables.nc");
    {
        std::unique_ptr<GDALDataset> ds(
            netcdf->CreateMultiDimensional(path.c_str(), nullptr, nullptr));
        ASSERT_NE(ds, nullptr);
        const std::shared_ptr<GDALGroup> root = ds->GetRootGroup();
        const auto y = root->CreateDimension("y", "", "", kHeight);
        const auto x = root->CreateDimension("x", "", "", kWidth);
        ASSERT_TRUE(y && x);
        for (const auto& [name, band] : {std::pair{"elevation", 1}, {"quality", 2}}) {
            const auto array =
                root->CreateMDArray(name, {y, x}, GDALExtendedDataType::Create(GDT_Float32));
            ASSERT_NE(array, nullptr) << name;
            std::vector<float> values;
            for (int r = 0; r < kHeight; ++r)
                for (int c = 0; c < kWidth; ++c) values.push_back(storedValue(band, c, r));
            const std::array<GUInt64, 2> start{0, 0};
            const std::array<std::size_t, 2> count{kHeight, kWidth};
            ASSERT_TRUE(array->Write(start.data(), count.data(), nullptr, nullptr,
                                     GDALExtendedDataType::Create(GDT_Float32), values.data()));
        }
    }
    const auto container = test::openOne(path);
    ASSERT_FALSE(container);
    const std::string& message = container.error().message;
    EXPECT_NE(message.find("holds 2 subdatasets"), std::string::npos) << message;
    const std::string quality = "NETCDF:\"" + path + "\":quality";
    EXPECT_NE(message.find(quality), std::string::npos) << message;
    EXPECT_NE(message.find("NETCDF:\"" + path + "\":elevation"), std::string::npos) << message;

    auto reader = test::openOne(quality);
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_EQ(reader.value()->info().width, kWidth);
    const std::vector<float> all = readAll(*reader.value());
    // Whatever way the file stores its rows, the values are the variable's, not its
    // neighbour's.
    for (const float v : all) EXPECT_GE(v, storedValue(2, 0, 0));
    EXPECT_EQ(*std::max_element(all.begin(), all.end()), storedValue(2, kWidth - 1, kHeight - 1));

    // A name GDAL cannot open is an error naming it, not "no such file"; a variable the file
    // lacks is said so, naming the file, with the subdatasets it does hold (issue 52: it was
    // netCDF's "netcdf error #-49 … netcdfdataset.cpp").
    const std::string slope = "NETCDF:\"" + path + "\":slope";
    const auto wrong = test::openOne(slope);
    ASSERT_FALSE(wrong);
    const std::string& refusal = wrong.error().message;
    EXPECT_TRUE(refusal.starts_with(slope + ": subdataset slope does not exist: " + path +
                                    " holds 2 subdatasets; give one of them as the input:"))
        << refusal;
    EXPECT_NE(refusal.find("\n  " + quality), std::string::npos) << refusal;
    EXPECT_NE(refusal.find("\n  NETCDF:\"" + path + "\":elevation"), std::string::npos) << refusal;
    EXPECT_EQ(refusal.find("no such file"), std::string::npos);
    EXPECT_EQ(refusal.find("netcdf error"), std::string::npos) << refusal;
    // The file part unquoted, as GDAL takes it too.
    const auto unquoted = test::openOne("NETCDF:" + path + ":slope");
    ASSERT_FALSE(unquoted);
    EXPECT_NE(unquoted.error().message.find("subdataset slope does not exist: " + path),
              std::string::npos)
        << unquoted.error().message;
}

TEST_F(GdalInputsTest, InlineVrtIsADataset) {
    const std::string tiff = copyTo(memoryDataset(2, kNorthUp), "GTiff", "source.tif");
    const std::string vrt = "<VRTDataset rasterXSize=\"" + std::to_string(kWidth) +
                            "\" rasterYSize=\"" + std::to_string(kHeight) +
                            "\"><VRTRasterBand dataType=\"Float32\" band=\"1\"><SimpleSource>"
                            "<SourceFilename>" +
                            tiff +
                            "</SourceFilename><SourceBand>2</SourceBand></SimpleSource>"
                            "</VRTRasterBand></VRTDataset>";
    auto reader = test::openOne(vrt);
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_EQ(readAll(*reader.value())[1], storedValue(2, 1, 0));
}

// A file inside a zip, by GDAL's /vsizip/ name: no such file on disk, yet an input.
TEST_F(GdalInputsTest, ZippedFileIsReadThroughVsizip) {
    const std::string tiff = copyTo(memoryDataset(1, kNorthUp), "GTiff", "inside.tif");
    const std::vector<char> bytes = test::readBytes(tiff);
    const std::string name = "/vsizip/" + m_dir.file("dems.zip") + "/inside.tif";
    VSILFILE* zipped = VSIFOpenL(name.c_str(), "wb");
    ASSERT_NE(zipped, nullptr) << "GDAL cannot write " << name;
    EXPECT_EQ(VSIFWriteL(bytes.data(), 1, bytes.size(), zipped), bytes.size());
    VSIFCloseL(zipped);
    auto reader = test::openOne(name);
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_EQ(reader.value()->info().readerName, "gdal");
    EXPECT_EQ(readAll(*reader.value())[7], storedValue(1, 2, 1));
}

// A grid stored south to north, or east to west, reads north-up: each height where GDAL's
// geotransform puts it, and the georeference of the north-west corner.
TEST_F(GdalInputsTest, FlippedGridsReadNorthUpWhereGdalPutsTheirHeights) {
    struct Case {
        const char* name;
        std::array<double, 6> gt;
        bool rowsFlipped, columnsFlipped;
    };
    const double west = 500000.0, north = 5200000.0, step = 10.0;
    const std::vector<Case> cases{
        {"south-up.tif", {west, step, 0.0, north - kHeight * step, 0.0, step}, true, false},
        {"east-to-west.tif", {west + kWidth * step, -step, 0.0, north, 0.0, -step}, false, true},
        {"both.tif",
         {west + kWidth * step, -step, 0.0, north - kHeight * step, 0.0, step},
         true,
         true},
        {"south-up.nc", {west, step, 0.0, north - kHeight * step, 0.0, step}, true, false},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string name = c.name;
        const std::string path =
            copyTo(memoryDataset(1, c.gt), name.ends_with(".nc") ? "netCDF" : "GTiff", name);
        auto reader = test::openOne(path);
        ASSERT_TRUE(reader) << reader.error().message;
        const DemInfo& info = reader.value()->info();
        EXPECT_EQ(info.georeference.originX, west);
        EXPECT_EQ(info.georeference.originY, north);
        EXPECT_EQ(info.georeference.pixelSizeX, step);
        EXPECT_EQ(info.georeference.pixelSizeY, step);
        // What GDAL says is at each sample's centre, through its own geotransform of the file.
        GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
        ASSERT_NE(ds, nullptr);
        std::array<double, 6> gt{};
        ds->GetGeoTransform(gt.data());
        std::vector<float> stored(kWidth * kHeight);
        ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, kWidth, kHeight, stored.data(),
                                                 kWidth, kHeight, GDT_Float32, 0, 0, nullptr),
                  CE_None);
        GDALClose(ds);
        const bool rows = gt[5] > 0.0, columns = gt[1] < 0.0;
        EXPECT_EQ(info.rowsFlipped, rows);
        EXPECT_EQ(info.columnsFlipped, columns);
        if (!name.ends_with(".nc")) {
            EXPECT_EQ(rows, c.rowsFlipped);
            EXPECT_EQ(columns, c.columnsFlipped);
        }
        const std::vector<float> read = readAll(*reader.value());
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                // Our sample (x, y) is centred at west + (x + ½)·step, north − (y + ½)·step;
                // find the stored sample GDAL centres there.
                const double mx = west + (x + 0.5) * step, my = north - (y + 0.5) * step;
                const auto sx = static_cast<int>(std::floor((mx - gt[0]) / gt[1]));
                const auto sy = static_cast<int>(std::floor((my - gt[3]) / gt[5]));
                EXPECT_EQ(read[static_cast<std::size_t>(y * kWidth + x)],
                          stored[static_cast<std::size_t>(sy * kWidth + sx)])
                    << "sample (" << x << ", " << y << ")";
            }
        }
    }
}

// A rotated grid (30°) and a sheared one: GDAL's warper resamples them onto a north-up
// grid in their CRS at their finer spacing. storedValue is a plane in the stored column
// and row, and bilinear interpolation (and its extension over the rim) is exact on a
// plane, so every resampled sample is that plane at its place in the source.
TEST_F(GdalInputsTest, RotatedAndShearedGridsAreResampledOntoANorthUpGrid) {
    const double c = 10.0 * std::cos(M_PI / 6.0), s = 10.0 * std::sin(M_PI / 6.0);
    const std::array<std::array<double, 6>, 2> placements = {
        std::array<double, 6>{500000.0, c, s, 5200000.0, s, -c},
        std::array<double, 6>{500000.0, 10.0, 4.0, 5200000.0, 0.0, -10.0}};
    int file = 0;
    for (const std::array<double, 6>& gt : placements) {
        SCOPED_TRACE(::testing::PrintToString(gt));
        const std::string path =
            copyTo(memoryDataset(1, gt), "GTiff", "tilted" + std::to_string(file++) + ".tif");
        const auto reader = test::openOne(path);
        ASSERT_TRUE(reader) << reader.error().message;
        const DemInfo& info = reader.value()->info();
        ASSERT_TRUE(info.resampledFrom);
        const ResampledGrid& from = *info.resampledFrom;
        EXPECT_EQ(from.width, kWidth);
        EXPECT_EQ(from.height, kHeight);
        EXPECT_EQ(from.geoTransform, gt);
        EXPECT_DOUBLE_EQ(info.georeference.pixelSizeX, 10.0);  // the finer axis' spacing
        EXPECT_DOUBLE_EQ(info.georeference.pixelSizeY, 10.0);
        EXPECT_EQ(info.georeference.epsg, 32610);
        ASSERT_FALSE(info.warnings.empty());
        EXPECT_NE(info.warnings.back().find("resampled"), std::string::npos);

        // Every source sample lies inside the grid, where its map position says.
        const std::array<double, 6>& a = from.toGrid;
        for (int r = 0; r < kHeight; ++r)
            for (int col = 0; col < kWidth; ++col) {
                const double x = a[0] + a[1] * col + a[2] * r, y = a[3] + a[4] * col + a[5] * r;
                EXPECT_GE(x, -1e-9);
                EXPECT_LE(x, double(info.width - 1) + 1e-9);
                EXPECT_GE(y, -1e-9);
                EXPECT_LE(y, double(info.height - 1) + 1e-9);
                const double mapX = gt[0] + (col + 0.5) * gt[1] + (r + 0.5) * gt[2];
                EXPECT_NEAR(info.georeference.originX + (x + 0.5) * 10.0, mapX, 1e-6);
            }

        // The resampled samples: the plane wherever the source reaches, no-data beyond.
        const std::vector<float> resampled = readAll(*reader.value());
        const double det = a[1] * a[5] - a[2] * a[4];
        int inside = 0, valid = 0;
        for (std::int64_t y = 0; y < info.height; ++y)
            for (std::int64_t x = 0; x < info.width; ++x) {
                const double dx = double(x) - a[0], dy = double(y) - a[3];
                const double col = (a[5] * dx - a[2] * dy) / det,
                             row = (a[1] * dy - a[4] * dx) / det;
                const float value = resampled[static_cast<std::size_t>(y * info.width + x)];
                const bool inHull = col >= 0 && col <= kWidth - 1 && row >= 0 && row <= kHeight - 1;
                inside += inHull ? 1 : 0;
                if (std::isnan(value)) {
                    EXPECT_FALSE(inHull) << x << ", " << y;
                    continue;
                }
                ++valid;
                EXPECT_NEAR(value, 50.0 + 10.0 * row + col, 1e-3) << x << ", " << y;
            }
        EXPECT_GT(inside, 0);
        EXPECT_GT(valid, inside);  // the rim around the source, extended
        EXPECT_LT(valid, info.width * info.height);

        // The source's own samples, as stored.
        DemReader* original = reader.value()->originalSamples();
        ASSERT_NE(original, nullptr);
        EXPECT_EQ(original->info().width, kWidth);
        EXPECT_EQ(original->info().height, kHeight);
        const std::vector<float> stored = readAll(*original);
        for (int r = 0; r < kHeight; ++r)
            for (int col = 0; col < kWidth; ++col)
                EXPECT_EQ(stored[static_cast<std::size_t>(r * kWidth + col)],
                          storedValue(1, col, r));
    }
}

TEST_F(GdalInputsTest, RotatedGridRefusesAPlacementFromTheCommandLine) {
    const std::string path = copyTo(memoryDataset(1, {500000.0, 10.0, 2.0, 5200000.0, 2.0, -10.0}),
                                    "GTiff", "rotated.tif");
    DemOpenOptions options;
    options.pixelSize = 5.0;
    const auto reader = test::openOne(path, options);
    ASSERT_FALSE(reader);
    EXPECT_NE(reader.error().message.find("rotated or sheared"), std::string::npos)
        << reader.error().message;
    EXPECT_EQ(reader.error().message.rfind(path, 0), 0U);
}

// A projected grid going into a globe pyramid (issue 20): GDAL's warper puts it onto a
// longitude/latitude grid on WGS84 at its ground spacing, every one of its samples inside,
// each placed where PROJ says. Bilinear interpolation in the source is exact on a plane
// (storedValue), so every resampled sample inside the source's hull is the plane at its
// place in the source.
TEST_F(GdalInputsTest, ProjectedGridIsResampledOntoLongitudeLatitudeForTheGlobe) {
    const std::string path = copyTo(memoryDataset(1, kNorthUp), "GTiff", "utm.tif");
    DemOpenOptions options;
    options.geographicGrid = true;
    const auto reader = test::openOne(path, options);
    ASSERT_TRUE(reader) << reader.error().message;
    DemReader& dem = *reader.value();
    const DemInfo& info = dem.info();
    const Georeference& geo = info.georeference;
    EXPECT_EQ(geo.crsKind, CrsKind::Geographic);
    EXPECT_EQ(geo.epsg, Georeference::kWgs84Geographic);
    ASSERT_TRUE(info.resampledFrom);
    EXPECT_NE(info.resampledFrom->fromCrs.find("UTM zone 10N"), std::string::npos);
    EXPECT_EQ(info.resampledFrom->width, kWidth);
    EXPECT_EQ(info.resampledFrom->height, kHeight);
    ASSERT_FALSE(info.warnings.empty());
    EXPECT_NE(info.warnings.back().find("longitude/latitude grid on WGS84"), std::string::npos)
        << info.warnings.back();
    ASSERT_NE(dem.originalSamples(), nullptr);
    const std::vector<float> own = readAll(*dem.originalSamples());
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            EXPECT_EQ(own[static_cast<std::size_t>(y * kWidth + x)], storedValue(1, x, y));

    // The grid's spacing on the ground: as fine as the source's, and not much finer. On
    // the central meridian UTM's scale is 0.9996, so 10 m of the grid are 10.004 m.
    const double latitude = (geo.originY - 0.5 * double(info.height) * geo.pixelSizeY) * M_PI / 180;
    const double a = 6378137.0, e2 = 0.00669437999014, w = 1 - e2 * std::pow(std::sin(latitude), 2);
    const double metresNorth = geo.pixelSizeY * M_PI / 180 * a * (1 - e2) / std::pow(w, 1.5);
    const double metresEast = geo.pixelSizeX * M_PI / 180 * a / std::sqrt(w) * std::cos(latitude);
    const double ground = 10.0 / 0.9996;
    EXPECT_LE(metresNorth, ground + 1e-3);
    EXPECT_LE(metresEast, ground + 1e-3);
    EXPECT_GT(metresNorth, 9.9);
    EXPECT_GT(metresEast, 9.9);

    // Every own sample lies inside the grid, where PROJ (asked here on its own) places it.
    OGRSpatialReference utm, wgs84;
    utm.importFromEPSG(32610);
    wgs84.importFromEPSG(4326);
    utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    const std::unique_ptr<OGRCoordinateTransformation> toWgs84(
        OGRCreateCoordinateTransformation(&utm, &wgs84));
    const std::unique_ptr<OGRCoordinateTransformation> toUtm(
        OGRCreateCoordinateTransformation(&wgs84, &utm));
    ASSERT_TRUE(toWgs84 && toUtm);
    for (int r = 0; r < kHeight; ++r) {
        std::vector<double> x(kWidth), y(kWidth);
        ASSERT_TRUE(dem.placeOriginalSamples(0, r, x, y));
        for (int col = 0; col < kWidth; ++col) {
            const auto i = static_cast<std::size_t>(col);
            EXPECT_GE(x[i], -1e-9);
            EXPECT_LE(x[i], double(info.width - 1) + 1e-9);
            EXPECT_GE(y[i], -1e-9);
            EXPECT_LE(y[i], double(info.height - 1) + 1e-9);
            double lon = kNorthUp[0] + (col + 0.5) * kNorthUp[1];
            double lat = kNorthUp[3] + (r + 0.5) * kNorthUp[5];
            ASSERT_TRUE(toWgs84->Transform(1, &lon, &lat));
            EXPECT_NEAR(geo.originX + (x[i] + 0.5) * geo.pixelSizeX, lon, 1e-9);
            EXPECT_NEAR(geo.originY - (y[i] + 0.5) * geo.pixelSizeY, lat, 1e-9);
        }
    }

    // The resampled samples: the plane wherever the source's hull reaches.
    const std::vector<float> resampled = readAll(dem);
    int inside = 0;
    for (std::int64_t gy = 0; gy < info.height; ++gy)
        for (std::int64_t gx = 0; gx < info.width; ++gx) {
            double east = geo.originX + (double(gx) + 0.5) * geo.pixelSizeX;
            double north = geo.originY - (double(gy) + 0.5) * geo.pixelSizeY;
            ASSERT_TRUE(toUtm->Transform(1, &east, &north));
            const double col = (east - kNorthUp[0]) / kNorthUp[1] - 0.5;
            const double row = (north - kNorthUp[3]) / kNorthUp[5] - 0.5;
            if (col < 0 || col > kWidth - 1 || row < 0 || row > kHeight - 1) continue;
            ++inside;
            const float value = resampled[static_cast<std::size_t>(gy * info.width + gx)];
            EXPECT_NEAR(value, 50.0 + 10.0 * row + col, 1e-3) << gx << ", " << gy;
        }
    EXPECT_GT(inside, kWidth * kHeight / 2);

    // Without the option it opens in its own CRS, as a planar pyramid takes it.
    const auto planar = test::openOne(path);
    ASSERT_TRUE(planar) << planar.error().message;
    EXPECT_EQ(planar.value()->info().georeference.crsKind, CrsKind::Projected);
    EXPECT_FALSE(planar.value()->info().resampledFrom);
}

TEST_F(GdalInputsTest, ProjectedGridForTheGlobeRefusesWhatItCannotPlace) {
    DemOpenOptions options;
    options.geographicGrid = true;
    // The refusal of a one-sample grid with `geoTransform` in EPSG:`epsg`, written as `name`:
    // it must name the file first.
    const auto refusalOf = [&](const std::array<double, 6>& geoTransform, int epsg,
                               const std::string& name) {
        GDALDataset* ds = memoryDataset(1, geoTransform);
        OGRSpatialReference crs;
        crs.importFromEPSG(epsg);
        ds->SetSpatialRef(&crs);
        const std::string path = copyTo(ds, "GTiff", name);
        const auto reader = test::openOne(path, options);
        if (reader) return std::string("opened");
        EXPECT_EQ(reader.error().message.rfind(path, 0), 0U) << reader.error().message;
        return reader.error().message;
    };
    const std::string west = copyTo(memoryDataset(1, kNorthUp), "GTiff", "west.tif");
    {
        DemOpenOptions placed = options;
        placed.pixelSize = 5.0;
        const auto reader = test::openOne(west, placed);
        ASSERT_FALSE(reader);
        EXPECT_EQ(reader.error().message.rfind(west, 0), 0U);
        EXPECT_NE(reader.error().message.find("--spacing"), std::string::npos)
            << reader.error().message;
    }
    {
        std::array<double, 6> east = kNorthUp;
        east[0] += kWidth * kNorthUp[1];
        const std::string eastPath = copyTo(memoryDataset(1, east), "GTiff", "east.tif");
        const auto reader = openDem({west, eastPath}, options);
        ASSERT_FALSE(reader);
        EXPECT_NE(reader.error().message.find("gdalbuildvrt"), std::string::npos)
            << reader.error().message;
    }
    {
        // Antarctic polar stereographic samples 5 km apart across and 500 km along: a strip
        // over the south pole, whose grid round the pole needs a thousand times its samples.
        const std::string message =
            refusalOf({-12500.0, 5000.0, 0.0, 1000000.0, 0.0, -500000.0}, 3031, "strip.tif");
        EXPECT_NE(message.find("round the pole"), std::string::npos) << message;
        EXPECT_NE(message.find("over 64 times as many"), std::string::npos) << message;
    }
    {
        // World Mercator samples 5,500 km apart: 198° of longitude, 48° S to 48° N. Neither
        // one interval of longitude nor a cap round a pole holds them. (Across the
        // antimeridian or round a pole a footprint is placed: GlobePyramidTest.)
        const std::string message = refusalOf(
            {-13750000.0, 5500000.0, 0.0, 8000000.0, 0.0, -4000000.0}, 3395, "wide.tif");
        EXPECT_NE(message.find("cut it into parts first"), std::string::npos) << message;
    }
}

TEST_F(GdalInputsTest, NorthUpGridsAreNotResampled) {
    const auto reader = test::openOne(copyTo(memoryDataset(1, kNorthUp), "GTiff", "plain.tif"));
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_FALSE(reader.value()->info().resampledFrom);
    EXPECT_EQ(reader.value()->originalSamples(), nullptr);
}

}  // namespace
}  // namespace terrain::io
