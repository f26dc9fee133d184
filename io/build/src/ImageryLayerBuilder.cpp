// buildImageryLayer (ImageryLayerBuilder.h). Two passes: the first finds the tiles the image
// overlaps (a coarse grid of each tile's texels placed on the image, depth first from the
// roots), the second samples and writes them on a few threads, each with its own image.
#include "terrain/build/ImageryLayerBuilder.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/ImageryMips.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/PatchIdHash.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <thread>
#include <unordered_map>
#include <unordered_set>

namespace terrain::io {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Points a side of the grid that tests whether a tile overlaps the image (its stored texels
/// 0, 8, …, 256: the outer edges included).
constexpr int kProbePoints = 33;
/// The most blocks of the averaged image one tile reads (a tile stretched across the image,
/// at a pole of a geographic image): past it the tile reads a coarser average.
constexpr std::int64_t kMaxWindowBlocks = std::int64_t{4096} * 4096;

/// Where texels lie on the terrain, in the terrain points ImageryImage takes.
class TerrainFrame {
public:
    explicit TerrainFrame(const PyramidManifest& m) : m_manifest(m) {}
    bool globe() const { return m_manifest.globe.has_value(); }
    int rootLevel() const { return globe() ? ManifestGlobe::kLevelOffset : 0; }
    std::int64_t tilesX(int level) const {
        if (globe()) return globe::kCubeFaces * (std::int64_t{1} << (level - rootLevel()));
        return planarImageryTilesX(m_manifest.layout, level);
    }
    std::int64_t tilesY(int level) const {
        if (globe()) return std::int64_t{1} << (level - rootLevel());
        return planarImageryTilesY(m_manifest.layout, level);
    }
    /// The terrain point of stored-texel position (a, b) (texel centres at k + 0.5), where
    /// planarImageryPoint or globeImageryPoint puts it. Computed from the position counted
    /// over the frame's interiors (an exact number), so a tile's border texel and the same
    /// texel in its neighbour's interior land on the same point to the last bit, and sample
    /// the same colour: the coarser levels made of them (CoarserLevel) match across tiles.
    void point(const PatchId& id, double a, double b, double& x, double& y) const {
        constexpr double interior = kImageryInteriorTexels;
        const double border = kImageryBorderTexels;
        if (!globe()) {
            const PyramidLayout& l = m_manifest.layout;
            const double perTexel =
                std::ldexp(static_cast<double>(l.patchQuads()), l.finestLevel() - id.level) /
                interior;
            // Past the DEM's last sample nothing is drawn but the filter's reach at the
            // terrain's edge: there the edge's colour continues (as GL's clamp to edge), so
            // the edge is drawn in the imagery's colour, not half in the tint.
            x = std::clamp((static_cast<double>(id.x) * interior + a - border) * perTexel, 0.0,
                           static_cast<double>(l.rasterWidth() - 1));
            y = std::clamp((static_cast<double>(id.y) * interior + b - border) * perTexel, 0.0,
                           static_cast<double>(l.rasterHeight() - 1));
            return;
        }
        const int faceLevel = id.level - rootLevel();
        const std::int64_t perFace = std::int64_t{1} << faceLevel;
        const std::int64_t face = id.x / perFace;
        const double perTexel = std::ldexp(1.0, -faceLevel) / interior;
        const double s =
            (static_cast<double>(id.x - face * perFace) * interior + a - border) * perTexel;
        const double t = (static_cast<double>(id.y) * interior + b - border) * perTexel;
        const globe::Geodetic g =
            globe::Wgs84::geodeticOfNormal(globe::directionOf(static_cast<int>(face), s, t));
        x = g.longitudeDeg;
        y = g.latitudeDeg;
    }
    /// A texel's size at `level`: finest samples (plane), radians of arc (globe, the face's
    /// mean).
    double texelSize(int level) const {
        if (globe())
            return std::numbers::pi / 2.0 / kImageryInteriorTexels /
                   std::ldexp(1.0, level - rootLevel());
        const PyramidLayout& l = m_manifest.layout;
        return std::ldexp(static_cast<double>(l.patchQuads()), l.finestLevel() - level) /
               kImageryInteriorTexels;
    }
    /// The distance of two terrain points in texelSize's unit.
    double distance(double x0, double y0, double x1, double y1) const {
        if (!globe()) return std::hypot(x1 - x0, y1 - y0);
        const glm::dvec3 a = globe::Wgs84::normalAt(y0, x0), b = globe::Wgs84::normalAt(y1, x1);
        return std::acos(std::clamp(a.x * b.x + a.y * b.y + a.z * b.z, -1.0, 1.0));
    }
    /// The tiles of `level` whose texel grid continues tile `id`'s (same level) without a
    /// turn: the plane's, or the cube face's of `id`. In that frame a tile's index along
    /// each axis runs over 0 … count − 1 from `first` (the global index of index 0).
    struct FrameAxis {
        std::int64_t first = 0, count = 0;
    };
    FrameAxis axisX(int level, const PatchId& id) const {
        if (!globe()) return {0, tilesX(level)};
        const std::int64_t perFace = tilesY(level);
        const std::int64_t idPerFace = tilesY(id.level);
        return {id.x / idPerFace * perFace, perFace};
    }
    FrameAxis axisY(int level) const { return {0, tilesY(level)}; }
    int deepestLevel() const {
        return globe() ? rootLevel() + kMaxGlobeFaceLevel : m_manifest.layout.finestLevel() + 16;
    }

private:
    const PyramidManifest& m_manifest;
};

/// Whether a pixel position lies on the image or within `margin` pixels of it.
bool nearImage(const ImageryImage& image, double x, double y, double margin) {
    if (!std::isfinite(x) || !std::isfinite(y)) return false;
    const bool inX =
        image.wrapsColumns() || (x > -margin && x < static_cast<double>(image.width()) + margin);
    return inX && y > -margin && y < static_cast<double>(image.height()) + margin;
}

/// Whether tile `id` overlaps the image: a grid of its texel positions, each taken as wide
/// as the grid's spacing there.
bool overlaps(const TerrainFrame& frame, ImageryImage& image, const PatchId& id,
              std::vector<double>& xs, std::vector<double>& ys) {
    constexpr int n = kProbePoints;
    xs.resize(n * n);
    ys.resize(n * n);
    const double step = static_cast<double>(kImageryTileTexels) / (n - 1);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            frame.point(id, i * step, j * step, xs[static_cast<std::size_t>(j * n + i)],
                        ys[static_cast<std::size_t>(j * n + i)]);
    image.toPixels(xs, ys);
    const double period = static_cast<double>(image.width());
    // The spacing to a neighbour, the nearer of the two along each axis: a point beside a
    // discontinuity of the image's CRS (the antimeridian of a geographic image) keeps the
    // spacing of its other side.
    const auto spacing = [&](std::size_t at, std::size_t other) {
        double dx = std::abs(xs[other] - xs[at]);
        if (image.wrapsColumns()) dx = std::min(dx, std::abs(period - dx));
        return std::max(dx, std::abs(ys[other] - ys[at]));
    };
    // A point on the tile's edge has one neighbour along an axis, which may lie across the
    // discontinuity: no spacing counts more than 4 times the tile's median one.
    std::vector<double> all;
    for (std::size_t at = 0; at + 1 < xs.size(); ++at)
        if (const double d = spacing(at, at + 1); std::isfinite(d)) all.push_back(d);
    if (all.empty()) return false;
    std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2),
                     all.end());
    const double largest = 4.0 * all[all.size() / 2];
    const auto nearer = [](double a, double b) {
        return std::isfinite(a) && std::isfinite(b) ? std::min(a, b) : std::isfinite(a) ? a : b;
    };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::size_t at = static_cast<std::size_t>(j * n + i);
            const double inRow =
                nearer(i > 0 ? spacing(at, at - 1) : kNaN, i + 1 < n ? spacing(at, at + 1) : kNaN);
            const double inColumn =
                nearer(j > 0 ? spacing(at, at - n) : kNaN, j + 1 < n ? spacing(at, at + n) : kNaN);
            const double margin = std::min(std::max(inRow, inColumn), largest);
            if (std::isfinite(margin) && nearImage(image, xs[at], ys[at], margin)) {
                return true;
            }
        }
    return false;
}

/// The present tiles, level by level, with their children's bits.
struct PlannedTile {
    PatchId id;
    std::uint8_t presentChildren = 0;
};

struct Planner {
    const TerrainFrame& frame;
    ImageryImage& image;
    int finestLevel = 0;
    std::vector<PlannedTile> tiles;
    std::vector<double> xs, ys;

    // Depth first: whether `id` is present (it is when it overlaps, or is a root).
    bool visit(const PatchId& id, bool root) {
        if (id.x >= frame.tilesX(id.level) || id.y >= frame.tilesY(id.level)) return false;
        if (!overlaps(frame, image, id, xs, ys) && !root) return false;
        const std::size_t at = tiles.size();
        tiles.push_back({id, 0});
        if (id.level < finestLevel)
            for (int c = 0; c < 4; ++c) {
                const PatchId child{id.level + 1, id.x * 2 + (c & 1), id.y * 2 + (c >> 1)};
                if (visit(child, false)) tiles[at].presentChildren |= std::uint8_t(1U << c);
            }
        return true;
    }
};

/// A window of the image averaged over blocks of 2^k, read for one tile.
struct BlockWindow {
    int k = 0;
    std::int64_t blocksX = 0, blocksY = 0;  // of the whole averaged image
    std::int64_t x0 = 0, y0 = 0;            // the window's first block (x0 may be < 0: wrapped)
    int w = 0, h = 0;
    /// The image wraps around in x and the window holds its whole width: a block past either
    /// end is the one a turn away (a tile around a pole takes every longitude, and unwrapped
    /// around its centre its texels still meet across the meridian opposite the centre's).
    bool wholeTurn = false;
    std::vector<std::uint8_t> rgba;

    // Premultiplied colour of block (bx, by) of the averaged image; 0 outside it.
    void blockAt(std::int64_t bx, std::int64_t by, double out[4]) const {
        out[0] = out[1] = out[2] = out[3] = 0.0;
        std::int64_t lx = bx - x0;
        const std::int64_t ly = by - y0;
        if (wholeTurn) lx = (lx % blocksX + blocksX) % blocksX;
        if (ly < 0 || ly >= h || lx < 0 || lx >= w) return;
        if (by < 0 || by >= blocksY) return;
        const std::uint8_t* p = &rgba[static_cast<std::size_t>(ly * w + lx) * 4];
        const double a = p[3] / 255.0;
        out[0] = p[0] * a;
        out[1] = p[1] * a;
        out[2] = p[2] * a;
        out[3] = p[3];
    }
};

/// Every interior texel of `tile` has alpha 255.
bool interiorOpaque(const ImageryTile& tile) {
    constexpr int n = kImageryTileTexels;
    for (int r = kImageryBorderTexels; r < n - kImageryBorderTexels; ++r)
        for (int col = kImageryBorderTexels; col < n - kImageryBorderTexels; ++col)
            if (tile.rgba[(static_cast<std::size_t>(r) * n + static_cast<std::size_t>(col)) * 4 +
                          3] != 255)
                return false;
    return true;
}

class TileSampler {
public:
    TileSampler(const TerrainFrame& frame, ImageryImage& image, std::vector<int> levelK,
                std::vector<bool> superSample)
        : m_frame(frame),
          m_image(image),
          m_levelK(std::move(levelK)),
          m_superSample(std::move(superSample)) {}

    Status sample(const PatchId& id, ImageryTile& tile) {
        constexpr int n = kImageryTileTexels;
        constexpr std::size_t texels = std::size_t{n} * n;
        // A texel wider than the blocks it reads takes the mean of 2 × 2 points spread over
        // its area (a box filter): one bilinear point would alias the image's finest detail
        // into a beat a few texels long, which the coarser levels, made of this one's means,
        // would keep.
        const int points = m_superSample[static_cast<std::size_t>(id.level)] ? 4 : 1;
        m_xs.resize(texels * static_cast<std::size_t>(points));
        m_ys.resize(m_xs.size());
        for (int p = 0; p < points; ++p) {
            const double dx = points == 1 ? 0.5 : 0.25 + 0.5 * (p & 1);
            const double dy = points == 1 ? 0.5 : 0.25 + 0.5 * (p >> 1);
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const std::size_t at =
                        static_cast<std::size_t>(p) * texels + static_cast<std::size_t>(j * n + i);
                    m_frame.point(id, i + dx, j + dy, m_xs[at], m_ys[at]);
                }
        }
        m_image.toPixels(m_xs, m_ys);
        const bool wraps = m_image.wrapsColumns();
        const double width = static_cast<double>(m_image.width());
        // Unwrap around the tile's centre, so that a tile across the image's east edge reads
        // one window that continues past it. The turns added are kept apart: a point's
        // bilinear weights come from its own x, so a border texel and its neighbour's interior
        // texel, unwrapped around two centres, weigh the same blocks the same to the last bit.
        m_turns.assign(m_xs.size(), 0);
        if (wraps) {
            const double centre = m_xs[static_cast<std::size_t>(n / 2 * n + n / 2)];
            if (std::isfinite(centre))
                for (std::size_t at = 0; at < m_xs.size(); ++at)
                    if (std::isfinite(m_xs[at])) {
                        m_turns[at] =
                            static_cast<std::int64_t>(std::round((centre - m_xs[at]) / width));
                    }
        }
        m_unwrapped.resize(m_xs.size());
        for (std::size_t at = 0; at < m_xs.size(); ++at)
            m_unwrapped[at] = m_xs[at] + width * static_cast<double>(m_turns[at]);
        BlockWindow& win = m_window;
        win.k = m_levelK[static_cast<std::size_t>(id.level)];
        for (;; ++win.k) {
            const double scale = std::ldexp(1.0, win.k);
            win.blocksX = (m_image.width() + (std::int64_t{1} << win.k) - 1) >> win.k;
            win.blocksY = (m_image.height() + (std::int64_t{1} << win.k) - 1) >> win.k;
            double minX = std::numeric_limits<double>::infinity(), maxX = -minX, minY = minX,
                   maxY = -minX;
            for (std::size_t t = 0; t < m_xs.size(); ++t) {
                if (!std::isfinite(m_xs[t]) || !std::isfinite(m_ys[t])) continue;
                minX = std::min(minX, m_unwrapped[t] / scale);
                maxX = std::max(maxX, m_unwrapped[t] / scale);
                minY = std::min(minY, m_ys[t] / scale);
                maxY = std::max(maxY, m_ys[t] / scale);
            }
            if (!(minX <= maxX)) {  // nothing placed
                win.w = win.h = 0;
                win.wholeTurn = false;
                break;
            }
            std::int64_t x0 = static_cast<std::int64_t>(std::floor(minX)) - 1;
            std::int64_t x1 = static_cast<std::int64_t>(std::floor(maxX)) + 2;
            std::int64_t y0 = static_cast<std::int64_t>(std::floor(minY)) - 1;
            std::int64_t y1 = static_cast<std::int64_t>(std::floor(maxY)) + 2;
            y0 = std::clamp<std::int64_t>(y0, 0, win.blocksY);
            y1 = std::clamp<std::int64_t>(y1, 0, win.blocksY);
            if (wraps) {
                x1 = std::min(x1, x0 + win.blocksX);
            } else {
                x0 = std::clamp<std::int64_t>(x0, 0, win.blocksX);
                x1 = std::clamp<std::int64_t>(x1, 0, win.blocksX);
            }
            if ((x1 - x0) * (y1 - y0) > kMaxWindowBlocks) continue;
            win.x0 = x0;
            win.y0 = y0;
            win.w = static_cast<int>(x1 - x0);
            win.h = static_cast<int>(y1 - y0);
            win.wholeTurn = wraps && x1 - x0 == win.blocksX;
            break;
        }
        tile.id = id;
        tile.rgba.assign(kImageryTileBytes, 0);
        if (win.w > 0 && win.h > 0) {
            win.rgba.resize(static_cast<std::size_t>(win.w) * static_cast<std::size_t>(win.h) * 4);
            if (Status s = readWindow(); !s) return s;
            const double scale = std::ldexp(1.0, win.k);
            for (std::size_t t = 0; t < texels; ++t) {
                double c[4] = {0, 0, 0, 0};  // premultiplied, summed over the points
                for (int p = 0; p < points; ++p) {
                    const std::size_t at = static_cast<std::size_t>(p) * texels + t;
                    if (std::isfinite(m_xs[at]) && std::isfinite(m_ys[at]))
                        addBilinear(at, scale, wraps, width, c);
                }
                std::uint8_t* out = &tile.rgba[t * 4];
                if (c[3] <= 0.0) continue;
                const double unpremultiply = 255.0 / c[3];
                for (int ch = 0; ch < 3; ++ch)
                    out[ch] = static_cast<std::uint8_t>(
                        std::clamp(std::lround(c[ch] * unpremultiply), 0L, 255L));
                out[3] =
                    static_cast<std::uint8_t>(std::clamp(std::lround(c[3] / points), 0L, 255L));
            }
        }
        tile.info.present = true;
        tile.info.opaque = interiorOpaque(tile);
        return {};
    }

private:
    // Adds the window's bilinear sample between block centres at point `at`, premultiplied
    // by alpha, to c.
    void addBilinear(std::size_t at, double scale, bool wraps, double width, double c[4]) const {
        const BlockWindow& win = m_window;
        const double x = m_unwrapped[at], y = m_ys[at];
        // Where the turns are whole blocks (always at full resolution), the weights come from
        // the point's own x and the turns are added to the block index.
        const double turnBlocks = width * static_cast<double>(m_turns[at]) / scale;
        const bool wholeBlocks = turnBlocks == std::floor(turnBlocks);
        const double bx = (wholeBlocks ? m_xs[at] : x) / scale - 0.5, by = y / scale - 0.5;
        const double fx = std::floor(bx), fy = std::floor(by);
        const double wx = bx - fx, wy = by - fy;
        const auto ix = static_cast<std::int64_t>(fx) +
                        (wholeBlocks ? static_cast<std::int64_t>(turnBlocks) : 0),
                   iy = static_cast<std::int64_t>(fy);
        const double weights[4] = {(1 - wx) * (1 - wy), wx * (1 - wy), (1 - wx) * wy, wx * wy};
        // A pixel covers its whole area, up to the image's edge: a point on the image takes
        // the edge block past the last block centre (else the texels within half a block of
        // the edge would be half transparent: a band of the tint at the edge of an image laid
        // on the DEM's extent, or around the poles, which an image wrapping around the Earth
        // reaches with its first and last rows). Past the edge the colour fades out over half
        // a block.
        const bool onImage = y >= 0.0 && y <= static_cast<double>(m_image.height()) &&
                             (wraps || (x >= 0.0 && x <= width));
        double q[4];
        for (int corner = 0; corner < 4; ++corner) {
            std::int64_t cx = ix + (corner & 1), cy = iy + (corner >> 1);
            if (onImage) {
                cy = std::clamp<std::int64_t>(cy, 0, win.blocksY - 1);
                if (!wraps) cx = std::clamp<std::int64_t>(cx, 0, win.blocksX - 1);
            }
            win.blockAt(cx, cy, q);
            for (int ch = 0; ch < 4; ++ch) c[ch] += weights[corner] * q[ch];
        }
    }

    // Fills the window, in pieces where it continues past the image's east edge.
    Status readWindow() {
        BlockWindow& win = m_window;
        if (win.x0 >= 0 && win.x0 + win.w <= win.blocksX)
            return m_image.readBlocks(win.x0, win.y0, win.w, win.h, win.k, win.rgba);
        std::int64_t done = 0;
        while (done < win.w) {
            const std::int64_t bx = ((win.x0 + done) % win.blocksX + win.blocksX) % win.blocksX;
            const std::int64_t count = std::min<std::int64_t>(win.w - done, win.blocksX - bx);
            m_piece.resize(static_cast<std::size_t>(count * win.h) * 4);
            if (Status s =
                    m_image.readBlocks(bx, win.y0, static_cast<int>(count), win.h, win.k, m_piece);
                !s)
                return s;
            for (int row = 0; row < win.h; ++row)
                std::copy_n(&m_piece[static_cast<std::size_t>(row * count) * 4],
                            static_cast<std::size_t>(count) * 4,
                            &win.rgba[static_cast<std::size_t>(row * win.w + done) * 4]);
            done += count;
        }
        return {};
    }

    const TerrainFrame& m_frame;
    ImageryImage& m_image;
    std::vector<int> m_levelK;
    std::vector<bool> m_superSample;
    std::vector<double> m_xs, m_ys;     // the points in the image's pixels, as it places them
    std::vector<std::int64_t> m_turns;  // whole turns added to unwrap x around the tile
    std::vector<double> m_unwrapped;    // x + turns · width
    BlockWindow m_window;
    std::vector<std::uint8_t> m_piece;
};

/// Makes a tile of a coarser level from the finer level's stored texels: each texel the
/// alpha-weighted 2 × 2 mean (meanOfFourImageryTexels) of the four finer texels under it,
/// exactly as the runtime halves a tile into its mip 1 (makeImageryMips). So where the draw
/// turns from a tile's mip 1 to its parent's texels, both are the same bytes: no step at a
/// level change. Sampled afresh from the image (as the finest level is), a coarser level is
/// a differently filtered picture, and the change showed as a line (43.7 against 53.2 dB in
/// ImageryReferenceTest's close view; docs/imagery.md).
///
/// The four finer texels lie in one finer tile: the parent's own children for its interior,
/// its neighbours' children for its border (so its border holds what its neighbour's
/// interior holds: no seam at tile edges). Where that finer tile lies past the frame (the
/// plane's edge, a cube face's edge, where the grid turns), the texels come from the border
/// of the nearest finer tile in the frame when it stores them, else the texel is sampled
/// from the image as the finest level's are.
class CoarserLevel {
public:
    CoarserLevel(const TerrainFrame& frame, const ImageryLayerWriter& writer,
                 const std::unordered_set<PatchId, PatchIdHash>& present)
        : m_frame(frame), m_writer(writer), m_present(present) {}

    Status make(const PatchId& id, TileSampler& sampler, ImageryTile& tile) {
        const int finer = id.level + 1;
        const TerrainFrame::FrameAxis finerX = m_frame.axisX(finer, id);
        const AxisSource xs = axisSource(finerX.count, id.x - m_frame.axisX(id.level, id).first);
        const AxisSource ys = axisSource(m_frame.axisY(finer).count, id.y);
        if (xs.anyFresh || ys.anyFresh) {
            if (Status s = sampler.sample(id, tile); !s) return s;
        } else {
            tile.id = id;
            tile.rgba.assign(kImageryTileBytes, 0);
        }
        constexpr std::size_t n = kImageryTileTexels;
        static constexpr std::uint8_t kTransparent[4] = {0, 0, 0, 0};
        for (std::size_t row = 0; row < n; ++row) {
            if (ys.fresh[row]) continue;
            for (std::size_t column = 0; column < n; ++column) {
                if (xs.fresh[column]) continue;
                const PatchId child{finer, finerX.first + xs.tile[column], ys.tile[row]};
                const ImageryTile* source = nullptr;
                if (Status s = finerTile(child, source); !s) return s;
                std::array<const std::uint8_t*, 4> four{kTransparent, kTransparent, kTransparent,
                                                        kTransparent};
                if (source) {
                    const auto at = [&](int dx, int dy) {
                        return &source->rgba[((static_cast<std::size_t>(ys.stored[row] + dy)) * n +
                                              static_cast<std::size_t>(xs.stored[column] + dx)) *
                                             4];
                    };
                    four = {at(0, 0), at(1, 0), at(0, 1), at(1, 1)};
                }
                meanOfFourImageryTexels(four, &tile.rgba[(row * n + column) * 4]);
            }
        }
        tile.info.present = true;
        tile.info.opaque = interiorOpaque(tile);
        return {};
    }

private:
    /// Along one axis, for each stored texel of the coarser tile: which finer tile (its index
    /// in the frame) and which of its stored texels (the first of two) lie under it.
    struct AxisSource {
        std::array<std::int64_t, kImageryTileTexels> tile{};
        std::array<int, kImageryTileTexels> stored{};
        std::array<bool, kImageryTileTexels> fresh{};
        bool anyFresh = false;
    };

    /// `finerCount` finer tiles in the frame along the axis; the coarser tile is the frame's
    /// `index`-th.
    static AxisSource axisSource(std::int64_t finerCount, std::int64_t index) {
        constexpr std::int64_t interior = kImageryInteriorTexels;
        constexpr std::int64_t border = kImageryBorderTexels;
        AxisSource a;
        for (int k = 0; k < kImageryTileTexels; ++k) {
            // The first finer texel under stored texel k, counted over the frame's interiors.
            const std::int64_t g = 2 * (index * interior + k - border);
            std::int64_t t = g >= 0 ? g / interior : -((-g + interior - 1) / interior);
            t = std::clamp<std::int64_t>(t, 0, finerCount - 1);  // past the frame: a border
            const std::int64_t stored = g - t * interior + border;
            const auto at = static_cast<std::size_t>(k);
            a.tile[at] = t;
            a.stored[at] = static_cast<int>(stored);
            a.fresh[at] = stored < 0 || stored + 1 >= kImageryTileTexels;
            a.anyFresh = a.anyFresh || a.fresh[at];
        }
        return a;
    }

    /// The finer tile `id` as stored, or nullptr where the layer has none (the image does
    /// not reach it: transparent). Keeps the few a coarser tile reads.
    Status finerTile(const PatchId& id, const ImageryTile*& out) {
        out = nullptr;
        if (!m_present.contains(id)) return {};
        if (const auto kept = m_kept.find(id); kept != m_kept.end()) {
            out = kept->second.info.present ? &kept->second : nullptr;
            return {};
        }
        if (m_kept.size() >= kKeptTiles) m_kept.clear();
        ImageryTile& tile = m_kept[id];
        if (Status s = m_writer.readBack(id, tile); !s) {
            m_kept.erase(id);
            return s;
        }
        out = tile.info.present ? &tile : nullptr;
        return {};
    }

    /// A coarser tile reads at most 4 × 4 finer tiles; its neighbour in the list shares most.
    static constexpr std::size_t kKeptTiles = 32;

    const TerrainFrame& m_frame;
    const ImageryLayerWriter& m_writer;
    const std::unordered_set<PatchId, PatchIdHash>& m_present;
    std::unordered_map<PatchId, ImageryTile, PatchIdHash> m_kept;
};

/// The image's pixel at its centre, in the frame's unit: the smaller of its two sides.
double pixelSizeAtCentre(const TerrainFrame& frame, ImageryImage& image) {
    const double cx = static_cast<double>(image.width()) / 2.0;
    const double cy = static_cast<double>(image.height()) / 2.0;
    const auto c = image.toTerrain(cx, cy);
    const auto right = image.toTerrain(cx + 1.0, cy);
    const auto down = image.toTerrain(cx, cy + 1.0);
    return std::min(frame.distance(c[0], c[1], right[0], right[1]),
                    frame.distance(c[0], c[1], down[0], down[1]));
}

}  // namespace

Result<ImageryBuildReport> buildImageryLayer(const fs::path& pyramidDir,
                                             const PyramidManifest& manifest,
                                             const ImageryImageOpener& openImage,
                                             const ImageryBuildOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    Result<std::unique_ptr<ImageryImage>> first = openImage();
    if (!first) return first.error();
    ImageryImage& image = *first.value();
    const TerrainFrame frame(manifest);

    // The finest level: the first whose texel is no coarser than the image's pixel (times
    // options.finestTexelPixels).
    const double pixel = pixelSizeAtCentre(frame, image);
    if (!(pixel > 0.0) || !std::isfinite(pixel))
        return Error{
            fmt::format("{}: cannot place the image's centre on the pyramid's terrain "
                        "(its CRS does not transform there)",
                        image.name())};
    int finest = frame.rootLevel();
    while (finest < frame.deepestLevel() &&
           frame.texelSize(finest) > pixel * options.finestTexelPixels)
        ++finest;
    // Each level averages the image over blocks of 2^k pixels, k from its texel's size; a
    // texel wider than its blocks takes 2 × 2 points.
    std::vector<int> levelK(static_cast<std::size_t>(finest) + 1, 0);
    std::vector<bool> superSample(levelK.size(), false);
    for (int l = frame.rootLevel(); l <= finest; ++l) {
        const auto at = static_cast<std::size_t>(l);
        levelK[at] =
            std::max(0, static_cast<int>(std::floor(std::log2(frame.texelSize(l) / pixel))));
        superSample[at] = frame.texelSize(l) > pixel * std::ldexp(1.0, levelK[at]);
    }

    // Pass 1: which tiles.
    Planner planner{frame, image, finest, {}, {}, {}};
    bool any = false;
    for (std::int64_t y = 0; y < frame.tilesY(frame.rootLevel()); ++y)
        for (std::int64_t x = 0; x < frame.tilesX(frame.rootLevel()); ++x) {
            const PatchId root{frame.rootLevel(), x, y};
            any = overlaps(frame, image, root, planner.xs, planner.ys) || any;
            planner.visit(root, true);
        }
    if (!any)
        return Error{fmt::format("{}: does not overlap the pyramid {} (nothing written)",
                                 image.name(), pyramidDir.string())};

    // Pass 2: the finest level sampled from the image, then each coarser level made of the
    // finer level's stored texels (CoarserLevel), on a few threads, each with its own image.
    const fs::path layerDir = pyramidDir / "imagery" / options.name;
    Result<ImageryLayerWriter> writer = ImageryLayerWriter::create(layerDir, options.encoding);
    if (!writer) return writer.error();
    const unsigned threads = options.threads > 0
                                 ? static_cast<unsigned>(options.threads)
                                 : std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
    std::vector<std::vector<const PlannedTile*>> byLevel(static_cast<std::size_t>(finest) + 1);
    for (const PlannedTile& t : planner.tiles)
        byLevel[static_cast<std::size_t>(t.id.level)].push_back(&t);
    std::unordered_set<PatchId, PatchIdHash> present;
    for (const PlannedTile& t : planner.tiles) present.insert(t.id);

    std::mutex errorMutex;
    std::optional<Error> failure;
    for (int level = finest; level >= frame.rootLevel(); --level) {
        const std::vector<const PlannedTile*>& tiles = byLevel[static_cast<std::size_t>(level)];
        std::atomic<std::size_t> next{0};
        auto work = [&](ImageryImage* own) {
            std::unique_ptr<ImageryImage> opened;
            if (!own) {
                Result<std::unique_ptr<ImageryImage>> o = openImage();
                if (!o) {
                    std::lock_guard lock(errorMutex);
                    if (!failure) failure = o.error();
                    return;
                }
                opened = std::move(o).value();
                own = opened.get();
            }
            TileSampler sampler(frame, *own, levelK, superSample);
            CoarserLevel coarser(frame, writer.value(), present);
            ImageryTile tile;
            for (std::size_t i = next++; i < tiles.size(); i = next++) {
                {
                    std::lock_guard lock(errorMutex);
                    if (failure) return;
                }
                const PatchId& id = tiles[i]->id;
                Status s =
                    level == finest ? sampler.sample(id, tile) : coarser.make(id, sampler, tile);
                tile.info.presentChildren = tiles[i]->presentChildren;
                if (s) s = writer.value().writeTile(tile);
                if (!s) {
                    std::lock_guard lock(errorMutex);
                    if (!failure) failure = s.error();
                    return;
                }
            }
        };
        {
            std::vector<std::jthread> pool;
            for (unsigned t = 1; t < std::min<std::size_t>(threads, tiles.size()); ++t)
                pool.emplace_back(work, nullptr);
            work(&image);
        }
        if (failure) return *failure;
    }
    if (Status s = writer.value().finish(options.replaceExisting); !s) return s.error();

    ImageryBuildReport report;
    report.layer.name = options.name;
    report.layer.kind = std::string(ManifestImageryLayer::kStoredKind);
    report.layer.folder = (fs::path("imagery") / options.name).generic_string();
    report.layer.input = options.input;
    report.layer.codec = "webp";
    report.layer.coarsestLevel = frame.rootLevel();
    report.layer.finestLevel = finest;
    report.layer.opacity = options.opacity;
    report.tiles = writer.value().index().presentTiles();
    report.bytes = writer.value().index().bytes();
    report.pixelSizeAtCentre = pixel;
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace terrain::io
