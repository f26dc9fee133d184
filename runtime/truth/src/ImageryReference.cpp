// ImageryReference: the draped imagery's reference colour, pixel by pixel, on the CPU.
#include "terrain/runtime/ImageryReference.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/ImageryMips.h"
#include "terrain/runtime/ImageComparison.h"
#include "terrain/runtime/ImagerySelection.h"
#include "terrain/runtime/ImageryTexelsPerPixel.h"
#include "terrain/runtime/ScreenProjection.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace terrain::runtime {
namespace {

constexpr double kInterior = io::kImageryInteriorTexels;
constexpr double kBorder = io::kImageryBorderTexels;

/// Bilinear sample of an RGBA8 image `side` texels a side at texel coordinate (x, y) (texel
/// k's centre at k + 0.5), decoded to linear light first, as GL_SRGB8_ALPHA8 filters.
std::array<float, 4> bilinear(std::span<const std::uint8_t> rgba, int side, double x, double y) {
    const double fx = x - 0.5, fy = y - 0.5;
    const int x0 = std::clamp(static_cast<int>(std::floor(fx)), 0, side - 2);
    const int y0 = std::clamp(static_cast<int>(std::floor(fy)), 0, side - 2);
    const float wx = static_cast<float>(std::clamp(fx - x0, 0.0, 1.0));
    const float wy = static_cast<float>(std::clamp(fy - y0, 0.0, 1.0));
    std::array<float, 4> out{};
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            const float w = (i == 0 ? 1.0f - wx : wx) * (j == 0 ? 1.0f - wy : wy);
            const std::size_t at = 4 * (static_cast<std::size_t>(y0 + j) * side + (x0 + i));
            for (int c = 0; c < 3; ++c) out[c] += w * io::linearFromSrgb(rgba[at + c]);
            out[3] += w * static_cast<float>(rgba[at + 3]) / 255.0f;
        }
    }
    return out;
}

/// What the draw writes for a linear colour: terrain_imagery.glsl's sRGB encoding, then the
/// framebuffer's rounding to 8 bits.
std::uint8_t encoded(float linear) {
    const double c = std::clamp(static_cast<double>(linear), 0.0, 1.0);
    const double e = c < 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    return static_cast<std::uint8_t>(std::lround(e * 255.0));
}

}  // namespace

ImageryReference::ImageryReference(const io::PyramidManifest& manifest, std::vector<Layer> layers)
    : m_manifest(manifest), m_layers(std::move(layers)) {
    if (!manifest.globe) m_plane.emplace(manifest);
}

Result<std::unique_ptr<ImageryReference>> ImageryReference::open(
    const std::filesystem::path& pyramidDir, const io::PyramidManifest& manifest) {
    std::vector<Layer> layers;
    for (const io::ManifestImageryLayer& layer : manifest.imagery) {
        if (static_cast<int>(layers.size()) == kMaxDrawnImageryLayers) break;
        auto source = io::openImageryTiles(pyramidDir, manifest, layer);
        if (!source) return source.error();
        layers.push_back({layer, std::move(source).value()});
    }
    return std::unique_ptr<ImageryReference>(new ImageryReference(manifest, std::move(layers)));
}

ImageryReference::SurfacePoint ImageryReference::surfacePointOf(const glm::dvec3& world) const {
    if (m_plane) {
        const glm::dvec2 sample = m_plane->sampleOfWorld(world.x, world.y);
        return {0, sample.x, sample.y};
    }
    // The face point of the ellipsoid normal through the point: where its imagery lies
    // (globe::directionOf is that normal; ImageryTile.h, globeImageryPoint).
    const globe::Geodetic g = globe::Wgs84::toGeodetic(world);
    const globe::FacePoint f =
        globe::facePointOf(globe::Wgs84::normalAt(g.latitudeDeg, g.longitudeDeg));
    return {f.face, f.s, f.t};
}

glm::dvec2 ImageryReference::tileCoordinates(const SurfacePoint& point, int level) const {
    if (m_plane) {
        // planarImageryPoint's inverse: a tile of level l spans (N − 1) · 2^(finest − l)
        // finest samples.
        const io::PyramidLayout& layout = m_manifest.layout;
        const double span =
            std::ldexp(static_cast<double>(layout.patchQuads()), layout.finestLevel() - level);
        return {point.a / span, point.b / span};
    }
    // globeImageryPoint's inverse: 2^fl tiles a face side, faces side by side along x.
    const double perFace = std::ldexp(1.0, level - io::ManifestGlobe::kLevelOffset);
    const double limit = perFace * (1.0 - 1.0e-12);
    return {point.face * perFace + std::clamp(point.a * perFace, 0.0, limit),
            std::clamp(point.b * perFace, 0.0, limit)};
}

double ImageryReference::tilesPerUnit(int level) const {
    if (m_plane)
        return std::ldexp(1.0 / m_manifest.layout.patchQuads(),
                          level - m_manifest.layout.finestLevel());
    return std::ldexp(1.0, level - io::ManifestGlobe::kLevelOffset);
}

Result<const ImageryReference::CachedTile*> ImageryReference::tile(int layer,
                                                                   const io::PatchId& id) {
    const auto key = std::tuple{layer, id.level, id.x, id.y};
    if (const auto found = m_tiles.find(key); found != m_tiles.end()) return &found->second;
    if (m_tiles.size() >= kMaxTiles) m_tiles.clear();
    io::ImageryTile read;
    if (auto status = m_layers[static_cast<std::size_t>(layer)].source->readTile(id, read); !status)
        return status.error();
    CachedTile& cached = m_tiles[key];
    cached.present = read.info.present;
    // Its mips as the draw has them (made as the I/O thread makes them: ImageryMips.h).
    if (cached.present) io::makeImageryMips(read);
    cached.tile = std::move(read);
    return &cached;
}

Result<std::array<float, 4>> ImageryReference::sample(int layer, int level, int mip,
                                                      const SurfacePoint& point) {
    const io::ManifestImageryLayer& manifest = m_layers[static_cast<std::size_t>(layer)].manifest;
    for (int l = level; l >= manifest.coarsestLevel; --l) {
        const glm::dvec2 at = tileCoordinates(point, l);
        const io::PatchId id{l, static_cast<std::int64_t>(std::floor(at.x)),
                             static_cast<std::int64_t>(std::floor(at.y))};
        if (m_plane) {
            const io::PyramidLayout& layout = m_manifest.layout;
            if (id.x < 0 || id.y < 0 || id.x >= io::planarImageryTilesX(layout, l) ||
                id.y >= io::planarImageryTilesY(layout, l))
                return std::array<float, 4>{};
        }
        auto found = tile(layer, id);
        if (!found) return found.error();
        const CachedTile& t = *found.value();
        if (!t.present) continue;  // no imagery this fine here: the parent's texels
        // An ancestor's texels are `level − l` levels finer than the mip asked for: its own
        // mip 0 once the difference reaches it, as the draw samples an inherited quadrant.
        const int m = std::max(0, mip - (level - l));
        const double u = at.x - static_cast<double>(id.x);
        const double v = at.y - static_cast<double>(id.y);
        // ImageryTile.h: stored texel k's centre is at u = (k + 0.5 − border) / interior; a
        // mip halves the whole grid, border included.
        const double scale = std::ldexp(1.0, -m);
        return bilinear(io::imageryMip(t.tile, m), io::kImageryTileTexels >> m,
                        (kBorder + u * kInterior) * scale, (kBorder + v * kInterior) * scale);
    }
    return std::array<float, 4>{};
}

Result<ImageryFrameComparison> ImageryReference::compare(const Camera& camera,
                                                         const FrameImages& draped,
                                                         const TerrainStyle& style) {
    ImageryFrameComparison out;
    const int w = draped.width, h = draped.height;
    const std::size_t pixels = draped.pixels();
    out.referenceRgba.assign(4 * pixels, 0);
    if (m_layers.empty()) return out;
    const glm::dmat4 inverse = glm::inverse(camera.relativeViewProjection());
    std::vector<SurfacePoint> points(pixels);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            if (!draped.drawn(i)) continue;
            const glm::dvec3 world =
                camera.position + unprojectPixel(inverse, w, h, x, y, draped.depth[i]);
            points[i] = surfacePointOf(world);
        }
    }
    // The footprint along one axis, in units of the surface point (a sample, or a face's
    // whole side): the smaller of the steps to the two neighbours on the same surface, so
    // that a silhouette's far side does not count.
    const auto step = [&](std::size_t i, std::optional<std::size_t> before,
                          std::optional<std::size_t> after) -> std::optional<double> {
        std::optional<double> best;
        for (const std::optional<std::size_t> n : {before, after}) {
            if (!n || !draped.drawn(*n) || points[*n].face != points[i].face) continue;
            const double d = std::hypot(points[*n].a - points[i].a, points[*n].b - points[i].b);
            if (!best || d < *best) best = d;
        }
        return best;
    };
    const auto quadFootprint = [&](int x0, int y0) -> std::optional<double> {
        if (x0 + 1 >= w || y0 + 1 >= h) return std::nullopt;
        const std::size_t corner = static_cast<std::size_t>(y0) * w + x0;
        const std::size_t right = corner + 1, up = corner + static_cast<std::size_t>(w);
        for (const std::size_t n : {corner, right, up, up + 1})
            if (!draped.drawn(n) || points[n].face != points[corner].face) return std::nullopt;
        const double dx =
            std::hypot(points[right].a - points[corner].a, points[right].b - points[corner].b);
        const double dy =
            std::hypot(points[up].a - points[corner].a, points[up].b - points[corner].b);
        return std::max(dx, dy);
    };
    double squares = 0.0;
    std::vector<double> texelsPerPixel;
    const int layers = layerCount();
    const std::array<int, 4> order = imageryDrawOrder(style, layers);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            if (!draped.drawn(i)) continue;
            // The footprint along each axis from the nearer of the two neighbours (a
            // silhouette's far side does not count), the larger of the two axes'.
            std::optional<double> footprint;
            const auto sx = step(i, x > 0 ? std::optional(i - 1) : std::nullopt,
                                 x + 1 < w ? std::optional(i + 1) : std::nullopt);
            const auto sy = step(i, y > 0 ? std::optional(i - w) : std::nullopt,
                                 y + 1 < h ? std::optional(i + w) : std::nullopt);
            if (sx || sy) footprint = std::max(sx.value_or(0.0), sy.value_or(0.0));
            // As the GPU takes it where the pixel's 2 × 2 quad lies on one surface: the
            // differences across the quad, the same for its four pixels (coarse derivatives,
            // and llvmpipe's level of detail per quad). A quad cut by a silhouette differs
            // from the neighbours' by far more than the footprint changes across a pixel.
            if (const auto quad = quadFootprint(x & ~1, y & ~1);
                quad && footprint && *quad <= 1.5 * *footprint && *quad >= *footprint / 1.5)
                footprint = quad;
            if (!footprint) {
                ++out.unmeasuredPixels;
                continue;
            }
            std::array<float, 3> premultiplied{};
            float alpha = 0.0f;
            double finestTexelsPerPixel = 0.0;
            for (int drawn = 0; drawn < layers; ++drawn) {
                const int l = order[static_cast<std::size_t>(drawn)];
                const io::ManifestImageryLayer& manifest =
                    m_layers[static_cast<std::size_t>(l)].manifest;
                // The manifest's opacity times the style's, as TerrainRenderer sets them.
                const float opacity = static_cast<float>(manifest.opacity) *
                                      style.imageryOpacity[static_cast<std::size_t>(l)];
                if (opacity <= 0.0f) continue;
                // The footprint in the layer's finest texels, and the levels it reads.
                const double texels = *footprint * tilesPerUnit(manifest.finestLevel) * kInterior;
                const double lambda = std::log2(std::max(texels, 1.0e-30));
                // The level whose texels are no larger than the footprint (no coarser than
                // the layer's coarsest), and the mip within its tiles the rest asks for,
                // blended between two (trilinear), the tiles' three mips at most.
                const int level = std::max(
                    manifest.finestLevel - static_cast<int>(std::floor(std::max(lambda, 0.0))),
                    manifest.coarsestLevel);
                const double mip = std::clamp(lambda - (manifest.finestLevel - level), 0.0,
                                              static_cast<double>(io::kImageryTileMips - 1));
                const int mip0 =
                    std::min(static_cast<int>(std::floor(mip)), io::kImageryTileMips - 2);
                const float blend = static_cast<float>(mip - mip0);
                auto fine = sample(l, level, mip0, points[i]);
                if (!fine) return fine.error();
                std::array<float, 4> c = fine.value();
                if (blend > 0.0f) {
                    auto coarse = sample(l, level, mip0 + 1, points[i]);
                    if (!coarse) return coarse.error();
                    for (int k = 0; k < 4; ++k) c[k] += blend * (coarse.value()[k] - c[k]);
                }
                if (finestTexelsPerPixel == 0.0)
                    finestTexelsPerPixel = std::ldexp(texels, level - manifest.finestLevel);
                const float a = c[3] * opacity;
                for (int k = 0; k < 3; ++k)
                    premultiplied[k] = c[k] * a + premultiplied[k] * (1.0f - a);
                alpha = a + alpha * (1.0f - a);
            }
            // Wholly covered only: where the tint shows through, the colour is not imagery's.
            if (alpha < 1.0f - 1.0e-5f) {
                ++out.uncoveredPixels;
                continue;
            }
            int worst = 0;
            for (int k = 0; k < 3; ++k) {
                const std::uint8_t r = encoded(premultiplied[k] / alpha);
                out.referenceRgba[4 * i + k] = r;
                const int d = std::abs(int(r) - int(draped.rgba[4 * i + k]));
                worst = std::max(worst, d);
                squares += double(d) * d;
            }
            out.referenceRgba[4 * i + 3] = 255;
            out.maxLevels = std::max(out.maxLevels, worst);
            if (worst > ImageryFrameComparison::kVisibleLevels) ++out.visiblePixels;
            ++out.comparedPixels;
            if (finestTexelsPerPixel > 0.0) texelsPerPixel.push_back(finestTexelsPerPixel);
        }
    }
    if (out.comparedPixels > 0) {
        out.rmse = std::sqrt(squares / (3.0 * static_cast<double>(out.comparedPixels)));
        out.psnrDb = out.rmse > 0.0 ? 20.0 * std::log10(255.0 / out.rmse) : kIdenticalPsnrDb;
    }
    const ImageryTexelsPerPixel texels = summariseTexelsPerPixel(std::move(texelsPerPixel));
    if (texels.pixels > 0) {
        out.texelsPerPixelP50 = texels.p50;
        out.texelsPerPixelInRange = texels.inRange;
    }
    return out;
}

}  // namespace terrain::runtime
