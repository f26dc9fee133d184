// ImageryTile: one tile of an imagery layer draped on the terrain (issue 47,
// docs/imagery.md). Imagery lies on the terrain's own tiling: the tile of layout patch
// (level, x, y) covers exactly that patch's extent (the planar patch grid, or a cube face's
// patch on the globe), so the runtime finds a pixel's imagery by the same quadtree it draws
// the heights with. Imagery may be finer than the DEM: its levels continue below the
// pyramid's finest (each level halves the patch, as above it), and it may cover only part
// of the terrain (absent children, transparent texels).
//
// Texel grid. A tile is kImageryTileTexels² RGBA8 texels: kImageryInteriorTexels² interior
// texels covering the patch, and a border of kImageryBorderTexels on each side that
// continues the same grid outward (sampled from the same source, across patch and cube-face
// edges), so bilinear, mip-mapped and anisotropic filtering near a tile's edge read the same
// colours its neighbour holds: no seam at patch, level or tile boundaries. Stored texel k
// (0 … kImageryTileTexels − 1, column or row) has its centre at patch-local coordinate
//     u = (k + 0.5 − kImageryBorderTexels) / kImageryInteriorTexels,
// where u = 0 is the patch's first sample column (row) and u = 1 its last, exactly where the
// heights' samples 0 and N − 1 lie (planarImageryPoint, globeImageryPoint). Rows run like
// the heights' (row 0 at the smallest layout y: north on a north-up plane, a face's t = min).
#pragma once

#include "terrain/globe/CubeSphere.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <cstdint>
#include <span>
#include <vector>

namespace terrain::io {

/// Texels of one tile a side, border included: a power of two, so that the tile's own mips
/// halve it exactly (the border halves with it: 4, 2, 1 texels at mips 0, 1, 2).
inline constexpr int kImageryTileTexels = 256;
/// Border texels on each side, from the neighbours' area.
inline constexpr int kImageryBorderTexels = 4;
/// Interior texels a side: the patch's extent.
inline constexpr int kImageryInteriorTexels = kImageryTileTexels - 2 * kImageryBorderTexels;
/// Mip levels of a tile that keep a border of whole texels (256, 128, 64): what the draw may
/// sample from a tile before it takes its parent instead.
inline constexpr int kImageryTileMips = 3;
/// Bytes of one decoded tile (RGBA8).
inline constexpr std::size_t kImageryTileBytes =
    std::size_t{kImageryTileTexels} * kImageryTileTexels * 4;
/// Bytes of mip `mip` of a tile (RGBA8, (kImageryTileTexels >> mip)² texels).
constexpr std::size_t imageryMipBytes(int mip) { return kImageryTileBytes >> (2 * mip); }
/// Bytes of a tile's mips below its texels (1 … kImageryTileMips − 1), one after the other.
inline constexpr std::size_t kImageryMipChainBytes = [] {
    std::size_t bytes = 0;
    for (int mip = 1; mip < kImageryTileMips; ++mip) bytes += imageryMipBytes(mip);
    return bytes;
}();

struct ImageryTileInfo {
    /// The tile exists in its layer (the layer's image overlaps the patch). Every root tile
    /// of a layer is present, transparent where the image does not reach.
    bool present = false;
    /// Which of its four children exist, bit (cy · 2 + cx) for the child at offset (cx, cy):
    /// the runtime learns from a tile where finer imagery is without asking the disk.
    std::uint8_t presentChildren = 0;
    /// Every interior texel has alpha 255: a layer under it cannot show through.
    bool opaque = false;
    bool operator==(const ImageryTileInfo&) const = default;
};

struct ImageryTile {
    PatchId id;  ///< the layout patch it covers (level may exceed the pyramid's finest)
    ImageryTileInfo info;
    /// kImageryTileTexels² texels, row-major, 4 bytes each (R, G, B, A; straight alpha, not
    /// premultiplied; sRGB-encoded colour as images store it). Empty when not present.
    std::vector<std::uint8_t> rgba;
    /// kImageryMipChainBytes: mips 1 … kImageryTileMips − 1 of rgba, one after the other,
    /// made by the I/O thread (makeImageryMips) so the render thread only uploads them.
    /// Empty when not present, and in a tile as a layer's file or source yields it.
    std::vector<std::uint8_t> mips;
};

/// Mip `mip` of `tile`, (kImageryTileTexels >> mip)² RGBA8 texels: its texels at 0, else from
/// tile.mips (made by makeImageryMips: ImageryMips.h).
inline std::span<const std::uint8_t> imageryMip(const ImageryTile& tile, int mip) {
    if (mip == 0) return tile.rgba;
    std::size_t offset = 0;
    for (int below = 1; below < mip; ++below) offset += imageryMipBytes(below);
    return std::span<const std::uint8_t>(tile.mips).subspan(offset, imageryMipBytes(mip));
}

/// Tiles across (x) and down (y) a planar layer's level `level`: the layout's patches, and
/// past its finest level (imagery finer than the DEM) the finest's halved again per level.
inline std::int64_t planarImageryTilesX(const PyramidLayout& layout, int level) {
    const int finest = layout.finestLevel();
    return level <= finest ? layout.patchesX(level) : layout.patchesX(finest) << (level - finest);
}
inline std::int64_t planarImageryTilesY(const PyramidLayout& layout, int level) {
    const int finest = layout.finestLevel();
    return level <= finest ? layout.patchesY(level) : layout.patchesY(finest) << (level - finest);
}

/// Patch-local coordinate (0 at the patch's first sample, 1 at its last) of a point given in
/// stored-texel units along one axis (0 at the tile's outer edge, k + 0.5 the centre of
/// stored texel k).
inline double imageryPatchLocal(double storedTexel) {
    return (storedTexel - kImageryBorderTexels) / kImageryInteriorTexels;
}

/// A point of a planar pyramid's finest level, in its sample coordinates (column, row;
/// fractional): where patch-local (u, v) of layout patch `id` lies. `id.level` may exceed
/// the layout's finest level (imagery finer than the DEM): a patch of level l spans
/// (N − 1) · 2^(finest − l) finest samples, a fraction of one below the finest level.
struct PlanarSamplePoint {
    double column = 0.0;
    double row = 0.0;
};
PlanarSamplePoint planarImageryPoint(const PyramidLayout& layout, const PatchId& id, double u,
                                     double v);

/// The face point of patch-local (u, v) of a globe pyramid's layout patch `id` (its level ≥
/// ManifestGlobe::kLevelOffset; it may exceed the pyramid's finest): face level
/// fl = level − kLevelOffset, face = x / 2^fl, s = (x mod 2^fl + u) / 2^fl, t = (y + v) / 2^fl,
/// as the heights' samples (GlobePatch.h). s and t fall outside [0, 1] in the border of a
/// patch on a face's edge: globe::directionOf continues across the cube edge there.
globe::FacePoint globeImageryPoint(const PatchId& id, double u, double v);

}  // namespace terrain::io
