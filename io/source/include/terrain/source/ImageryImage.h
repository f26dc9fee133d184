// ImageryImage: the picture an imagery layer is built from, as the layer builder sees it
// (issue 47, docs/imagery.md): a raster of RGBA8 pixels, where terrain points fall on it,
// and its pixels averaged over aligned blocks (the low-pass of the coarser levels). terrain::dem
// implements it over GDAL (openImageryImage); the builder opens no file itself.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/Georeference.h"

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace terrain::io {

/// Where an imagery layer's terrain lies, for placing an image on it: a planar pyramid's
/// sample grid (its georeference; its CRS may be unknown) or the globe (WGS84).
struct ImageryPlacement {
    bool globe = false;
    Georeference georeference;  ///< planar: the pyramid's (sample (c, r) at the pixel centre)
    std::int64_t rasterWidth = 0, rasterHeight = 0;  ///< planar: finest samples
    /// Planar only: lay the image over the DEM's extent whatever its georeference (its outer
    /// edges on the DEM's first and last samples): for a picture without one.
    bool demExtent = false;
};

class ImageryImage {
public:
    virtual ~ImageryImage() = default;

    /// The file, for messages.
    virtual const std::string& name() const = 0;
    virtual std::int64_t width() const = 0;
    virtual std::int64_t height() const = 0;
    /// Whether its columns continue across its east edge into its west one (a geographic
    /// image around the whole Earth).
    virtual bool wrapsColumns() const = 0;

    /// Terrain points to pixel positions, in place: (x, y) in pixels, (0, 0) at the image's
    /// north-west corner, (width, height) at its south-east one. Terrain points are the planar
    /// pyramid's finest-level sample coordinates (column, row), or on the globe (longitude,
    /// latitude) in degrees, WGS84 geodetic. A point the CRS transformation cannot place
    /// becomes NaN. Not thread-safe: one image per thread.
    virtual void toPixels(std::span<double> xs, std::span<double> ys) = 0;
    /// The terrain point of a pixel position (NaN where it cannot be placed).
    virtual std::array<double, 2> toTerrain(double x, double y) = 0;

    /// RGBA8 of a window of the image averaged over aligned blocks of 2^k × 2^k pixels: block
    /// (bx, by) averages pixels [bx·2^k, (bx + 1)·2^k) × [by·2^k, (by + 1)·2^k) (clipped to the
    /// image), blocks [bx0, bx0 + w) × [by0, by0 + h), all within the image's
    /// ceil(width / 2^k) × ceil(height / 2^k) blocks; no-data and transparent pixels are left
    /// out of the colour's average. `rgba` holds w · h · 4 bytes, row by row. Errors name the
    /// file.
    virtual Status readBlocks(std::int64_t bx0, std::int64_t by0, int w, int h, int k,
                              std::span<std::uint8_t> rgba) = 0;
};

}  // namespace terrain::io
