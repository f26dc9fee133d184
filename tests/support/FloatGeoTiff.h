// Writes a float32 GeoTIFF through GDAL for tests that need a georeferenced source of their
// own making (a rotated grid, hills with a hole): the samples, geotransform, EPSG code and
// no-data value as given. The including test links GDAL.
#pragma once

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace terrain::test {

/// `samples` (width × height, row-major) at `path`; returns `path`. A failed write is a test
/// failure.
inline std::string writeFloatGeoTiff(const std::string& path,
                                     const std::array<double, 6>& geoTransform, int width,
                                     int height, const std::vector<float>& samples,
                                     std::optional<double> noData, int epsg = 32610) {
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDataset* ds = driver->Create(path.c_str(), width, height, 1, GDT_Float32, nullptr);
    std::array<double, 6> gt = geoTransform;
    ds->SetGeoTransform(gt.data());
    OGRSpatialReference srs;
    srs.importFromEPSG(epsg);
    ds->SetSpatialRef(&srs);
    if (noData) ds->GetRasterBand(1)->SetNoDataValue(*noData);
    EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, width, height,
                                             const_cast<float*>(samples.data()), width, height,
                                             GDT_Float32, 0, 0, nullptr),
              CE_None);
    GDALClose(ds);
    return path;
}

}  // namespace terrain::test
