// buildImageryLayer: an imagery layer of a pyramid built from an image (issue 47,
// docs/imagery.md, "How a layer is built"). The finest level, the first whose texels are no
// coarser than the image's pixel at its centre, takes the image's colour where each texel
// lies on the terrain (planarImageryPoint or globeImageryPoint, then the image's own CRS);
// each coarser level is made of the finer one's 2 × 2 means, as the runtime makes a tile's
// mips, so the draw does not step where it turns from a tile to its parent. Only tiles the
// image overlaps are stored, each root tile always (transparent where the image does not
// reach). Memory stays bounded: a tile's window of the image, and a few finer tiles read
// back, at a time.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/ImageryLayerWriter.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/source/ImageryImage.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace terrain::io {

struct ImageryBuildOptions {
    std::string name;   ///< the layer's name: its folder is imagery/<name>
    std::string input;  ///< the image as the user named it (recorded in the manifest)
    ImageryEncoding encoding;
    double opacity = 1.0;
    bool replaceExisting = false;  ///< replace a layer folder of the same name
    /// The finest level is the first whose texel is at most this many image pixels (at the
    /// image's centre). 1 would keep every pixel's detail, but an image at a power-of-two
    /// multiple of the patch grid (a DEM's 2^n × finer picture, Blue Marble's 2048 columns
    /// on the cube's faces) has 256 pixels where a tile has 248 interior texels: texels
    /// 256/248 = 1.03 of its pixel, so a rule of 1 took the level below, of 4× the texels
    /// (the layer 2.6× Blue Marble's size for 3 % of resolution).
    double finestTexelPixels = 1.1;
    /// Threads encoding tiles (each opens its own image); 0: the hardware's.
    int threads = 0;
};

struct ImageryBuildReport {
    ManifestImageryLayer layer;      ///< what to record in the manifest
    std::int64_t tiles = 0;          ///< present tiles written
    std::int64_t bytes = 0;          ///< of the tile files
    double pixelSizeAtCentre = 0.0;  ///< the image's pixel, in finest samples or radians
    double seconds = 0.0;
};

/// Opens the image once per building thread.
using ImageryImageOpener = std::function<Result<std::unique_ptr<ImageryImage>>()>;

/// Builds the layer into `<pyramidDir>/imagery/<name>` (through ImageryLayerWriter: nothing
/// is left behind on failure). Refuses an image that does not overlap the pyramid. Does not
/// touch the manifest: the caller records report.layer (writeManifest).
Result<ImageryBuildReport> buildImageryLayer(const std::filesystem::path& pyramidDir,
                                             const PyramidManifest& manifest,
                                             const ImageryImageOpener& openImage,
                                             const ImageryBuildOptions& options);

}  // namespace terrain::io
