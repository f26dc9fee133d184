// The GDAL-backed DemReader, shared by the single-file reader and the VRT mosaic: band 1
// of a dataset read window by window through GDALRasterBand::RasterIO (GDAL's block
// cache keeps decoded blocks between the builder's bands).
#pragma once

#include <optional>
#include <string_view>
#include "terrain/dem/OpenDem.h"

#include "DemReaderFactories.h"
#include "GdalSession.h"

#include <vector>

namespace terrain::io::detail {

/// A rectangle of the raster in pixels (a mosaic input's footprint).
struct PixelRect {
    std::int64_t x = 0, y = 0, width = 0, height = 0;
};

enum class RotatedGrids { Refuse, Resample };

/// What band `band` (1-based; unset: band 1, with a warning when there are several) of a
/// dataset says about itself: size, sample type, no-data, scale/offset, the georeference
/// with the CRS, and whether rows or columns run backwards (read flipped). A rotated or
/// sheared geotransform is an Error, or with RotatedGrids::Resample is described in
/// `resampledFrom` (the size is the source's, the georeference only its CRS) for
/// openResampledGdalDem. Errors name `path`: complex samples, a band it does not have, no
/// raster band (listing the subdatasets a container holds instead).
Result<DemInfo> describeGdalDataset(GDALDataset& dataset, const std::string& path,
                                    std::optional<int> band = std::nullopt,
                                    RotatedGrids rotated = RotatedGrids::Refuse);

/// Metres per unit of a band's height unit (GDAL's unit type: netCDF/CF `units`): 1 for
/// metres or no unit, 1000 for km, 0.3048 for ft, 1200/3937 for US survey ft; nothing for
/// anything else (degrees, a temperature, ...), which a DEM reader must refuse.
std::optional<double> metresPerHeightUnit(std::string_view unit);

class GdalDemReader final : public DemReader {
public:
    /// `coverage`: for a mosaic with gaps, the inputs' footprints (samples outside all of
    /// them read as NaN); empty when the whole raster is covered.
    /// Reads band info.band (or `datasetBand` when the dataset numbers it otherwise),
    /// flipping rows and columns as info says.
    GdalDemReader(DemInfo info, GdalDataset dataset, std::vector<PixelRect> coverage = {},
                  int datasetBand = 0);

    const DemInfo& info() const override { return m_info; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override;

private:
    void maskUncovered(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                       std::span<float> out) const;

    DemInfo m_info;
    GdalDataset m_dataset;
    GDALRasterBand* m_band = nullptr;
    bool m_wide = false;  // read as Float64: int32/uint32/float64 do not fit a float
    std::vector<PixelRect> m_coverage;
    std::vector<double> m_wideScratch;
};

/// The reader of a rotated or sheared dataset described with RotatedGrids::Resample: GDAL's
/// warper resamples band info.band bilinearly onto the north-up grid, in the same CRS,
/// whose sample centres cover every source sample centre at the source's finest spacing;
/// originalSamples() reads the source's own grid. Options that place the raster (pixel
/// size, origin) are refused: the geotransform places it. Errors name info.path.
DemReaderResult openResampledGdalDem(DemInfo info, GdalDataset dataset,
                                     const DemOpenOptions& options);

/// For a globe pyramid (DemOpenOptions::geographicGrid): a projected (or rotated) dataset,
/// resampled by GDAL's warper (bilinear) onto a longitude/latitude grid on WGS84 whose sample
/// centres span its own sample centres, at its finest ground spacing; originalSamples() reads
/// its own grid and placeOriginalSamples() places those samples on the new one through PROJ.
/// Errors name `path`: no CRS or geotransform, a footprint across the antimeridian, over a
/// pole or wider than a hemisphere, options that place the raster (its geotransform does).
DemReaderResult openGeographicGdalDem(const std::string& path, const DemOpenOptions& options);

/// Opens `path` (a file checked first: exists, not empty, not a truncated netCDF classic
/// file; a GDAL dataset name as GDAL takes it) for reading. Errors start with the path and
/// carry GDAL's message, but for a subdataset its file does not hold, which lists the ones
/// it does. A dataset whose first band's blocks decode to more than maxDecodeBytes
/// (DemOpenOptions::maxDecodeBytes) is an Error too.
Result<GdalDataset> openGdalDataset(const std::string& path, std::uint64_t maxDecodeBytes);

}  // namespace terrain::io::detail
