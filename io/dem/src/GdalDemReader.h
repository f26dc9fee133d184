// The GDAL-backed DemReader, shared by the single-file reader and the VRT mosaic: band 1
// of a dataset read window by window through GDALRasterBand::RasterIO (GDAL's block
// cache keeps decoded blocks between the builder's bands).
#pragma once

#include <optional>
#include <string_view>

#include "DemReaderFactories.h"
#include "GdalSession.h"

#include <vector>

namespace terrain::io::detail {

/// A rectangle of the raster in pixels (a mosaic input's footprint).
struct PixelRect {
    std::int64_t x = 0, y = 0, width = 0, height = 0;
};

/// What a dataset says about itself: size, sample type, no-data, scale/offset and the
/// georeference with the CRS. Errors name `path`: complex samples, a rotated or sheared
/// geotransform, no raster band.
Result<DemInfo> describeGdalDataset(GDALDataset& dataset, const std::string& path);

/// Metres per unit of a band's height unit (GDAL's unit type: netCDF/CF `units`): 1 for
/// metres or no unit, 1000 for km, 0.3048 for ft, 1200/3937 for US survey ft; nothing for
/// anything else (degrees, a temperature, ...), which a DEM reader must refuse.
std::optional<double> metresPerHeightUnit(std::string_view unit);

class GdalDemReader final : public DemReader {
public:
    /// `coverage`: for a mosaic with gaps, the inputs' footprints (samples outside all of
    /// them read as NaN); empty when the whole raster is covered.
    GdalDemReader(DemInfo info, GdalDataset dataset, bool bottomUp,
                  std::vector<PixelRect> coverage = {});

    const DemInfo& info() const override { return m_info; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override;

private:
    void maskUncovered(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                       std::span<float> out) const;

    DemInfo m_info;
    GdalDataset m_dataset;
    GDALRasterBand* m_band = nullptr;
    bool m_wide = false;      // read as Float64: int32/uint32/float64 do not fit a float
    bool m_bottomUp = false;  // geotransform with rows running north: flip on read
    std::vector<PixelRect> m_coverage;
    std::vector<double> m_wideScratch;
};

/// Opens `path` (checked: exists, not empty, not a truncated netCDF classic file) for
/// reading. Errors start with the path and carry GDAL's message.
Result<GdalDataset> openGdalDataset(const std::string& path);

/// true when `dataset` has a geotransform whose rows run north (positive y step).
bool gdalRowsRunNorth(GDALDataset& dataset);

}  // namespace terrain::io::detail
