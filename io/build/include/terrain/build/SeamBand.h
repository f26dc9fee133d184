// SeamBand: where a finer globe source ends over a coarser one (GlobeSources, docs/globe.md,
// "How it works"), the band over which it is blended into the coarser one, as wide along each
// edge as the height step there needs for the slope the blend adds to stay within the
// source's own steep slopes: a 90 m tile 2 km above a 37 km grid at its edge gets a ramp as
// steep as its own mountainsides, not a wall over a fixed 24 pixels.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace terrain::io {

/// The edges of a source's extent.
enum class SeamEdge { West, East, North, South };
inline constexpr int kSeamEdges = 4;

class SeamBand {
public:
    /// The narrowest band, pixels: what every edge had before the band followed the step.
    static constexpr double kMinimumPixels = 24.0;
    /// How fast the width may change along an edge, pixels per pixel: slowly enough that the
    /// weight's slope along the edge stays a small part of its slope across (a quarter at
    /// most on a pixel as wide as it is high), which `fit` counts.
    static constexpr double kWidthChangePerPixel = 0.25;
    /// The widest band, as a share of the source's width (west and east edges) or height
    /// (north and south): beyond it the band would hide the source it blends in.
    static constexpr double kWidestShare = 0.25;

    /// What `fit` needs of a source of `width` × `height` pixels.
    struct Source {
        std::int64_t width = 0, height = 0;
        /// Which edges are edges: a grid wrapping the globe has no west or east one, a grid
        /// reaching a pole no edge there.
        std::array<bool, kSeamEdges> edges{};
        /// The largest slope a blend band `widthPx` wide at `edge` may add, metres per metre
        /// (the source's 99th-percentile slope over such a baseline across the edge); 0: any
        /// step needs the widest band.
        std::function<double(SeamEdge edge, double widthPx)> slopeLimit;
        /// A pixel's ground size on row `row`: east–west and north–south, metres.
        std::function<double(std::int64_t row)> eastWestMetres, northSouthMetres;
        /// The source's height minus the one it is blended into at pixel (column, row);
        /// nothing where it is blended into none.
        std::function<std::optional<double>(std::int64_t column, std::int64_t row)> step;
    };

    /// A band of kMinimumPixels along `edges` (empty: none).
    SeamBand(std::int64_t width, std::int64_t height, std::array<bool, kSeamEdges> edges);
    SeamBand() : SeamBand(0, 0, {}) {}

    /// The band whose blend adds at most `source.slopeLimit`: along each edge, at each pixel
    /// t along it, the narrowest width W(t) for which the slope the blend adds at every
    /// pixel d of the band there, |step(d)| · c · smoothstep'(d / W) / (W · pixel metres
    /// across), stays ≤ slopeLimit(W) (smoothstep' = 6u(1 − u), at most 1.5 in the band's
    /// middle; c ≥ 1 counts the weight's slope along the edge, where W changes by up to
    /// kWidthChangePerPixel a pixel), within kMinimumPixels … kWidestShare of the source.
    /// Sampled out from the edge only as deep as the band reaches (each widening samples the
    /// pixels it adds, until the width holds over all of them), and spread along the edge so
    /// it changes slowly.
    static SeamBand fit(const Source& source);

    /// The source's weight against the one beneath at (x, y): pixels east of its west edge
    /// and south of its north edge (pixel areas: 0 on the edge, the first pixel's centre at
    /// 0.5). smoothstep(min over the edges of distance / W(t) there), clamped to 0 … 1: 0 on
    /// an edge, 1 beyond every band, continuous at the corners (the nearer band, relative to
    /// its width, wins). 1 for a band without an edge.
    double weight(double x, double y) const;

    /// The edge whose band `weight` follows at (x, y) (the smallest distance / W), if any.
    std::optional<SeamEdge> governingEdge(double x, double y) const;

    bool hasEdge(SeamEdge edge) const { return !m_widths[index(edge)].empty(); }
    /// Pixels along an edge (the source's height for west and east, its width for north and
    /// south), and across it.
    std::int64_t along(SeamEdge edge) const;
    std::int64_t across(SeamEdge edge) const;
    /// The width at pixel t along the edge (a pixel centre's index; linear between them,
    /// clamped at the ends), pixels.
    double widthAt(SeamEdge edge, double t) const;
    /// The narrowest and widest widths over the edges, pixels (0 without an edge).
    double narrowestPixels() const;
    double widestPixels() const;
    /// Pixels along the edges where the step needed a band wider than kWidestShare allows:
    /// there the blend adds more than the limit.
    std::int64_t cappedPixels() const { return m_cappedPixels; }

    /// The pixel (column, row) `depth` pixels in from an edge at pixel t along it.
    std::pair<std::int64_t, std::int64_t> pixelAt(SeamEdge edge, std::int64_t t,
                                                  std::int64_t depth) const;

private:
    static std::size_t index(SeamEdge edge) { return static_cast<std::size_t>(edge); }
    /// The smallest distance / W over the edges at (x, y), and its edge.
    std::pair<double, std::optional<SeamEdge>> relativeDistance(double x, double y) const;

    std::int64_t m_width = 0, m_height = 0;
    std::array<std::vector<float>, kSeamEdges> m_widths;  // per pixel along; empty: no edge
    std::int64_t m_cappedPixels = 0;
};

}  // namespace terrain::io
