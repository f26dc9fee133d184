// Rotated and sheared rasters (issue 21): GDAL's warper resamples them, lazily and window by
// window, onto a north-up grid in their own CRS, and the source's own samples stay readable
// so that the pyramid's error bounds are made and checked against them, not against the
// resampled grid (PyramidBuilder, PyramidSourceCheck).
#include "terrain/dem/OpenDem.h"
#include "GdalDemReader.h"
#include "GdalWarp.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace terrain::io::detail {
namespace {

struct NorthUpGrid {
    double originX = 0.0;  // west edge of column 0
    double originY = 0.0;  // north edge of row 0
    double pixelSize = 0.0;
    std::int64_t width = 0, height = 0;
    std::array<double, 6> toGrid{};
};

// The north-up grid whose first and last sample centres are the extremes of the source's
// sample centres, so every source sample lies inside it (the bounds then cover each one),
// at the source's finer sample spacing of its two axes, so nothing the source resolves is
// lost.
Result<NorthUpGrid> northUpGridFor(const DemInfo& info) {
    const ResampledGrid& source = *info.resampledFrom;
    const std::array<double, 6>& gt = source.geoTransform;
    if (source.width < 2 || source.height < 2)
        return Error{
            fmt::format("{}: a rotated or sheared grid of {} × {} samples: too small to "
                        "resample (2 × 2 at least)",
                        info.path, source.width, source.height)};
    NorthUpGrid grid;
    grid.pixelSize = std::min(std::hypot(gt[1], gt[4]), std::hypot(gt[2], gt[5]));
    double minX = INFINITY, maxX = -INFINITY, minY = INFINITY, maxY = -INFINITY;
    for (const double c : {0.5, double(source.width) - 0.5})
        for (const double r : {0.5, double(source.height) - 0.5}) {
            const double x = gt[0] + c * gt[1] + r * gt[2], y = gt[3] + c * gt[4] + r * gt[5];
            minX = std::min(minX, x);
            maxX = std::max(maxX, x);
            minY = std::min(minY, y);
            maxY = std::max(maxY, y);
        }
    const double columns = std::ceil((maxX - minX) / grid.pixelSize - 1e-9) + 1.0;
    const double rows = std::ceil((maxY - minY) / grid.pixelSize - 1e-9) + 1.0;
    if (!(columns >= 1.0 && rows >= 1.0 && columns <= INT_MAX && rows <= INT_MAX))
        return Error{fmt::format(
            "{}: its geotransform ({}, {}, {}, {}, {}, {}) needs a north-up grid of {} × {} "
            "samples, more than GDAL's warper writes",
            info.path, gt[0], gt[1], gt[2], gt[3], gt[4], gt[5], columns, rows)};
    // A 45° rotation doubles the samples, pixels 3:1 triple them; far more is a placement
    // no DEM has (a damaged geotransform) and would only fill a disk.
    constexpr double kMostSamplesPerSource = 64.0;
    if (columns * rows > kMostSamplesPerSource * double(source.width) * double(source.height))
        return Error{fmt::format(
            "{}: its geotransform ({}, {}, {}, {}, {}, {}) needs a north-up grid of {} × {} "
            "samples, over {} times its own {} × {}: pixels that long and thin are not a DEM's",
            info.path, gt[0], gt[1], gt[2], gt[3], gt[4], gt[5], columns, rows,
            kMostSamplesPerSource, source.width, source.height)};
    grid.width = static_cast<std::int64_t>(columns);
    grid.height = static_cast<std::int64_t>(rows);
    grid.originX = minX - grid.pixelSize / 2.0;
    grid.originY = maxY + grid.pixelSize / 2.0;
    // Sample (c, r)'s centre, (c + ½, r + ½) through the geotransform, in the grid's samples.
    const double p = grid.pixelSize;
    grid.toGrid = {(gt[0] + 0.5 * gt[1] + 0.5 * gt[2] - minX) / p, gt[1] / p,  gt[2] / p,
                   (maxY - gt[3] - 0.5 * gt[4] - 0.5 * gt[5]) / p, -gt[4] / p, -gt[5] / p};
    return grid;
}

// The rim of the resampled grid. A source sample on the source's edge lies in a cell of
// the resampled grid whose corners lie up to a cell outside the source, where the warper
// gives nothing (no-data, later filled) or averages what it has, and the surface drawn
// through that cell would miss the sample by metres. Every sample of the resampled grid
// whose place in the source is outside the hull of the source's samples, but within a cell
// of it, is the bilinear function of the source's nearest edge cell, extended: exact on a
// plane, as the warper is inside. The edge cells' samples (two rows and two columns on
// each side) are read once.
class SourceEdgeExtension {
public:
    static Result<SourceEdgeExtension> read(DemReader& original, const ResampledGrid& grid) {
        SourceEdgeExtension e;
        e.m_width = grid.width;
        e.m_height = grid.height;
        const std::array<double, 6>& a = grid.toGrid;
        const double det = a[1] * a[5] - a[2] * a[4];
        // Source (c, r) of grid (x, y): the inverse of toGrid.
        e.m_fromGrid = {(-a[5] * a[0] + a[2] * a[3]) / det, a[5] / det,  -a[2] / det,
                        (a[4] * a[0] - a[1] * a[3]) / det,  -a[4] / det, a[1] / det};
        // How far a cell's corner can be from a point in it, per source axis.
        e.m_reach = std::max(std::abs(e.m_fromGrid[1]) + std::abs(e.m_fromGrid[2]),
                             std::abs(e.m_fromGrid[4]) + std::abs(e.m_fromGrid[5])) +
                    1e-9;
        const std::int64_t w = grid.width, h = grid.height;
        for (const std::int64_t r : {std::int64_t{0}, std::int64_t{1}, h - 2, h - 1}) {
            std::vector<float>& row = e.m_rows.emplace_back(static_cast<std::size_t>(w));
            if (Status s = original.readWindow(0, r, w, 1, row); !s) return s.error();
        }
        for (const std::int64_t c : {std::int64_t{0}, std::int64_t{1}, w - 2, w - 1}) {
            std::vector<float>& column = e.m_columns.emplace_back(static_cast<std::size_t>(h));
            if (Status s = original.readWindow(c, 0, 1, h, column); !s) return s.error();
        }
        return e;
    }

    void apply(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
               std::span<float> out) const {
        const std::array<double, 6>& b = m_fromGrid;
        const double lastC = double(m_width - 1), lastR = double(m_height - 1);
        for (std::int64_t j = 0; j < rows; ++j)
            for (std::int64_t i = 0; i < width; ++i) {
                const double x = double(x0 + i), y = double(y0 + j);
                const double c = b[0] + b[1] * x + b[2] * y, r = b[3] + b[4] * x + b[5] * y;
                const double outC = std::max(-c, c - lastC), outR = std::max(-r, r - lastR);
                if ((outC <= 0.0 && outR <= 0.0) || outC > m_reach || outR > m_reach) continue;
                out[static_cast<std::size_t>(j * width + i)] = extended(c, r);
            }
    }

private:
    // The bilinear function of the edge cell nearest (c, r), at (c, r).
    float extended(double c, double r) const {
        const std::int64_t c0 =
            std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(c)), 0, m_width - 2);
        const std::int64_t r0 =
            std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(r)), 0, m_height - 2);
        const double f = c - double(c0), g = r - double(r0);
        const double v = (1 - f) * (1 - g) * at(c0, r0) + f * (1 - g) * at(c0 + 1, r0) +
                         (1 - f) * g * at(c0, r0 + 1) + f * g * at(c0 + 1, r0 + 1);
        return static_cast<float>(v);  // NaN when a corner is no-data
    }

    // A sample of the edge rows or columns (the only ones an edge cell has).
    double at(std::int64_t c, std::int64_t r) const {
        const std::array<std::int64_t, 4> rows{0, 1, m_height - 2, m_height - 1};
        for (std::size_t k = 0; k < 4; ++k)
            if (r == rows[k]) return m_rows[k][static_cast<std::size_t>(c)];
        const std::array<std::int64_t, 4> columns{0, 1, m_width - 2, m_width - 1};
        for (std::size_t k = 0; k < 4; ++k)
            if (c == columns[k]) return m_columns[k][static_cast<std::size_t>(r)];
        return std::numeric_limits<double>::quiet_NaN();  // not an edge cell: unreachable
    }

    std::int64_t m_width = 0, m_height = 0;
    std::array<double, 6> m_fromGrid{};
    double m_reach = 0.0;
    std::vector<std::vector<float>> m_rows, m_columns;
};

// The source's samples on their own grid, and its resampling; the resampled reader reads
// the band VRT (if any), which reads the source, so they close in the opposite order.
class ResampledGdalDemReader final : public DemReader {
public:
    ResampledGdalDemReader(DemInfo info, std::unique_ptr<GdalDemReader> original, GdalDataset band,
                           std::unique_ptr<GdalDemReader> resampled, SourceEdgeExtension edges)
        : m_info(std::move(info)),
          m_original(std::move(original)),
          m_band(std::move(band)),
          m_resampled(std::move(resampled)),
          m_edges(std::move(edges)) {}

    const DemInfo& info() const override { return m_info; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        if (Status read = m_resampled->readWindow(x0, y0, width, rows, out); !read) return read;
        m_edges.apply(x0, y0, width, rows, out);
        return {};
    }
    DemReader* originalSamples() override { return m_original.get(); }
    Status placeOriginalSamples(std::int64_t firstColumn, std::int64_t row, std::span<double> x,
                                std::span<double> y) override {
        const std::array<double, 6>& a = m_info.resampledFrom->toGrid;
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double c = double(firstColumn + std::int64_t(i)), r = double(row);
            x[i] = a[0] + a[1] * c + a[2] * r;
            y[i] = a[3] + a[4] * c + a[5] * r;
        }
        return {};
    }

private:
    DemInfo m_info;
    std::unique_ptr<GdalDemReader> m_original;
    GdalDataset m_band;
    std::unique_ptr<GdalDemReader> m_resampled;
    SourceEdgeExtension m_edges;
};

}  // namespace

DemReaderResult openResampledGdalDem(DemInfo info, GdalDataset dataset,
                                     const DemOpenOptions& options) {
    if (options.pixelSize || options.originX || options.originY)
        return Error{fmt::format(
            "{}: the raster is rotated or sheared and its geotransform places it; a pixel size "
            "or origin cannot be given for it",
            info.path)};
    const Result<NorthUpGrid> made = northUpGridFor(info);
    if (!made) return made.error();
    const NorthUpGrid& grid = made.value();
    info.width = grid.width;
    info.height = grid.height;
    info.resampledFrom->toGrid = grid.toGrid;
    Georeference& geo = info.georeference;
    geo.pixelSizeX = geo.pixelSizeY = grid.pixelSize;
    geo.originX = grid.originX;
    geo.originY = grid.originY;
    info.hasGeoreference = true;
    if (Status s = applyDemOpenOptions(info, options); !s) return s.error();

    // The source's own samples: stored rows and columns, no placement.
    DemInfo own = info;
    own.width = info.resampledFrom->width;
    own.height = info.resampledFrom->height;
    own.resampledFrom.reset();
    own.hasGeoreference = false;
    own.georeference = Georeference{};
    own.georeference.crsKind = CrsKind::Unknown;
    own.warnings.clear();
    GDALDataset& source = *dataset;
    const GDALDataType type = source.GetRasterBand(info.band)->GetRasterDataType();
    const bool wide = isWideSampleType(type);
    auto original = std::make_unique<GdalDemReader>(std::move(own), std::move(dataset));
    Result<SourceEdgeExtension> edges = SourceEdgeExtension::read(*original, *info.resampledFrom);
    if (!edges) return edges.error();

    const double p = grid.pixelSize;
    Result<WarpedDataset> warped = warpBilinear(source, info,
                                                {.west = grid.originX,
                                                 .south = grid.originY - double(grid.height) * p,
                                                 .east = grid.originX + double(grid.width) * p,
                                                 .north = grid.originY,
                                                 .width = grid.width,
                                                 .height = grid.height,
                                                 .targetCrs = {},
                                                 .sourceCrs = {}},
                                                wide, "a north-up grid");
    if (!warped) return warped.error();

    const ResampledGrid& from = *info.resampledFrom;
    info.warnings.push_back(fmt::format(
        "{}: rotated or sheared grid ({} × {} samples, geotransform {:g}, {:g}, {:g}, {:g}, {:g}, "
        "{:g}) resampled {} by GDAL's warper onto a north-up grid of {} × {} at {:g}; the error "
        "bounds cover the source's own samples",
        info.path, from.width, from.height, from.geoTransform[0], from.geoTransform[1],
        from.geoTransform[2], from.geoTransform[3], from.geoTransform[4], from.geoTransform[5],
        from.method, grid.width, grid.height, grid.pixelSize));
    // The warper marks samples outside the source NaN and reads around no-data; its raw
    // values are interpolated, so none of them is the source's no-data value.
    DemInfo resampledInfo = info;
    resampledInfo.noDataValue.reset();
    resampledInfo.rowsFlipped = resampledInfo.columnsFlipped = false;
    auto resampled = std::make_unique<GdalDemReader>(
        std::move(resampledInfo), std::move(warped.value().warped), std::vector<PixelRect>{}, 1);
    return std::unique_ptr<DemReader>(std::make_unique<ResampledGdalDemReader>(
        std::move(info), std::move(original), std::move(warped.value().band), std::move(resampled),
        std::move(edges).value()));
}

}  // namespace terrain::io::detail
