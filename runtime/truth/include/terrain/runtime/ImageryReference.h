// ImageryReference: what the draped imagery should look like at each pixel of a drawn frame
// (issue 47's measure), computed on the CPU from the layers' tiles read straight from disk,
// with nothing streamed: every tile of every layer present at the level the pixel needs.
//
// The frame's own depth gives each pixel's point on the drawn surface, so the comparison
// measures the imagery alone (where it is placed, which level and mip it is drawn from,
// seams, streaming's stand-ins), not the geometry, which the screen-space error measures.
// Each pixel is filtered as the draw filters it, with every tile there: the footprint f in
// the layer's finest texels (from the neighbouring pixels' points, or from the pixel's 2 × 2
// quad where the quad lies on one surface, as the GPU's coarse derivatives are), λ = log2 f,
// the level whose texels are no larger than f, λ' = λ less the levels from the finest to it,
// and within that tile's mips (made as the I/O thread makes them: ImageryMips.h) the
// bilinear samples of mips ⌊λ'⌋ and ⌊λ'⌋ + 1 blended by the rest (trilinear), in linear light, straight alpha, as GL_SRGB8_ALPHA8 filters. An
// absent tile takes its parent's texels, as the draw does. Layers are composited as
// terrain_imagery.glsl composites them. (Across a level change the draw, and so this
// reference, go from a tile's mip 1 to its parent's mip 0, which the builder averages afresh
// from the image: the two are not the same texels, docs/imagery.md.)
// Isotropic: the measure is meant for a sampler without anisotropy (llvmpipe's, and
// gl::textureAnisotropyWorthFiltering there), where the draw's filter is the same shape.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/ImageryTileSource.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameImages.h"
#include "terrain/runtime/ImageComparison.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainStyle.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

namespace terrain::runtime {

struct ImageryFrameComparison {
    /// Pixels compared: drawn, and wholly covered by the reference's imagery (where it is
    /// partly transparent the tint shows through, which is not imagery's to measure).
    std::uint64_t comparedPixels = 0;
    /// Drawn pixels the reference leaves partly or wholly uncovered (not compared): where the
    /// layers do not reach, or where their own texels are transparent (a layer meant to cover
    /// the whole terrain shows a defect of its build here).
    std::uint64_t uncoveredPixels = 0;
    /// Drawn pixels whose footprint could not be told (no drawn neighbour on the same face).
    std::uint64_t unmeasuredPixels = 0;
    double rmse = 0.0;  ///< 8-bit levels, RGB, over the compared pixels
    double psnrDb = kIdenticalPsnrDb;  ///< as ImageComparison.h: identical images 100 dB
    int maxLevels = 0;  ///< largest difference of one channel, 8-bit levels
    /// Compared pixels whose largest channel difference exceeds kVisibleLevels.
    std::uint64_t visiblePixels = 0;
    /// The bottom layer's texels across a compared pixel at the level the ideal filter
    /// reads first (its median and share within 0.5–2; magnified pixels count below 1).
    double texelsPerPixelP50 = 0.0;
    double texelsPerPixelInRange = 0.0;
    /// The reference image, RGBA8 (rows bottom-up; alpha 0 where not compared).
    std::vector<std::uint8_t> referenceRgba;

    static constexpr int kVisibleLevels = 8;
};

class ImageryReference {
public:
    /// Opens the first kMaxDrawnImageryLayers layers of the pyramid at `pyramidDir` (a folder
    /// or the virtual planet's name). Errors name the layer. A pyramid without imagery opens
    /// with no layers (compare then compares nothing).
    static Result<std::unique_ptr<ImageryReference>> open(const std::filesystem::path& pyramidDir,
                                                          const io::PyramidManifest& manifest);

    int layerCount() const { return static_cast<int>(m_layers.size()); }

    /// `draped`: the frame drawn with imagery unlit and without fog (its colour is the
    /// imagery's where it covers the pixel wholly), `style`: the opacities and order it was
    /// drawn with. Errors: a tile that cannot be read (names the file).
    Result<ImageryFrameComparison> compare(const Camera& camera, const FrameImages& draped,
                                           const TerrainStyle& style);

private:
    struct Layer {
        io::ManifestImageryLayer manifest;
        std::unique_ptr<io::ImageryTileSource> source;
    };
    /// A decoded tile (RGBA8, sRGB colour, straight alpha) and its mips, as the pool makes
    /// them (ImageryMips): what the draw samples.
    struct CachedTile {
        bool present = false;
        io::ImageryTile tile;  ///< its texels and mips (ImageryTile::mips)
    };
    /// Where a pixel's point lies on the terrain's tiling: on the globe a cube face and its
    /// (s, t); on the plane the finest level's sample (column, row). Fractional.
    struct SurfacePoint {
        int face = 0;
        double a = 0.0;
        double b = 0.0;
    };

    ImageryReference(const io::PyramidManifest& manifest, std::vector<Layer> layers);
    SurfacePoint surfacePointOf(const glm::dvec3& world) const;
    /// `point` in tiles of `level`: the tile is (floor, floor), the patch's (u, v) the rest.
    glm::dvec2 tileCoordinates(const SurfacePoint& point, int level) const;
    /// Tiles of `level` across one unit of a SurfacePoint (a sample; a face's side).
    double tilesPerUnit(int level) const;
    Result<const CachedTile*> tile(int layer, const io::PatchId& id);
    /// Bilinear sample (linear light, straight alpha) of `layer`'s tile of `level` at its mip
    /// `mip`, from a coarser level's tile where it is absent, as the draw does; transparent
    /// where no level has one.
    Result<std::array<float, 4>> sample(int layer, int level, int mip, const SurfacePoint& point);

    io::PyramidManifest m_manifest;
    std::optional<TerrainGeometry> m_plane;
    std::vector<Layer> m_layers;
    /// Tiles read so far, by (layer, level, x, y); emptied past kMaxTiles.
    std::map<std::tuple<int, int, std::int64_t, std::int64_t>, CachedTile> m_tiles;
    static constexpr std::size_t kMaxTiles = 2048;
};

}  // namespace terrain::runtime
