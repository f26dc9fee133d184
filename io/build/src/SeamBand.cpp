#include "terrain/build/SeamBand.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::io {

namespace {

constexpr SeamEdge kEdges[kSeamEdges] = {SeamEdge::West, SeamEdge::East, SeamEdge::North,
                                         SeamEdge::South};

bool acrossColumns(SeamEdge edge) { return edge == SeamEdge::West || edge == SeamEdge::East; }

}  // namespace

SeamBand::SeamBand(std::int64_t width, std::int64_t height, std::array<bool, kSeamEdges> edges)
    : m_width(width), m_height(height) {
    for (SeamEdge edge : kEdges)
        if (edges[index(edge)])
            m_widths[index(edge)].assign(static_cast<std::size_t>(along(edge)),
                                         static_cast<float>(kMinimumPixels));
}

std::int64_t SeamBand::along(SeamEdge edge) const {
    return acrossColumns(edge) ? m_height : m_width;
}

std::int64_t SeamBand::across(SeamEdge edge) const {
    return acrossColumns(edge) ? m_width : m_height;
}

std::pair<std::int64_t, std::int64_t> SeamBand::pixelAt(SeamEdge edge, std::int64_t t,
                                                        std::int64_t depth) const {
    switch (edge) {
        case SeamEdge::West:
            return {depth, t};
        case SeamEdge::East:
            return {m_width - 1 - depth, t};
        case SeamEdge::North:
            return {t, depth};
        case SeamEdge::South:
            return {t, m_height - 1 - depth};
    }
    return {0, 0};
}

SeamBand SeamBand::fit(const Source& source) {
    SeamBand band(source.width, source.height, source.edges);
    // Per edge and pixel along it: the ground size across it, what the widening c counts
    // (where W changes by k a pixel, the weight's argument d / W changes along the edge by at
    // most k / (W · along metres) against 1 / (W · across metres) across), and |step| at each
    // pixel sampled out from the edge (0 where nothing lies beneath).
    struct EdgeFit {
        std::vector<double> acrossMetres, factor;
        std::vector<std::vector<float>> steps;
        std::int64_t capped = 0;
    };
    std::array<EdgeFit, kSeamEdges> fits;
    for (SeamEdge edge : kEdges) {
        if (!band.hasEdge(edge)) continue;
        EdgeFit& f = fits[index(edge)];
        const std::int64_t n = band.along(edge);
        f.steps.resize(static_cast<std::size_t>(n));
        for (std::int64_t t = 0; t < n; ++t) {
            const std::int64_t row = band.pixelAt(edge, t, 0).second;
            const double eastWest = source.eastWestMetres(row);
            const double northSouth = source.northSouthMetres(row);
            const double a = acrossColumns(edge) ? eastWest : northSouth;
            const double b = acrossColumns(edge) ? northSouth : eastWest;
            f.acrossMetres.push_back(a);
            f.factor.push_back(std::hypot(1.0, kWidthChangePerPixel * a / b));
        }
    }
    // All edges together, each widening where its steps need it: a pixel counts for the edge
    // whose band its weight follows (near a corner, the other edge's band may).
    for (bool changed = true; changed;) {
        changed = false;
        for (SeamEdge edge : kEdges) {
            if (!band.hasEdge(edge)) continue;
            EdgeFit& f = fits[index(edge)];
            std::vector<float>& widths = band.m_widths[index(edge)];
            const std::int64_t depthLimit = band.across(edge);
            const double widest =
                std::max(kMinimumPixels, kWidestShare * static_cast<double>(depthLimit));
            // Sample each position as deep as its band reaches now.
            for (std::size_t t = 0; t < widths.size(); ++t) {
                std::vector<float>& sampled = f.steps[t];
                const auto depth =
                    std::min(depthLimit, static_cast<std::int64_t>(std::ceil(double(widths[t]))));
                while (static_cast<std::int64_t>(sampled.size()) < depth) {
                    const auto [column, row] =
                        band.pixelAt(edge, static_cast<std::int64_t>(t),
                                     static_cast<std::int64_t>(sampled.size()));
                    const std::optional<double> step = source.step(column, row);
                    sampled.push_back(step ? static_cast<float>(std::abs(*step)) : 0.0f);
                    changed = true;
                }
            }
            // The width each position needs: the slope the blend adds across the band at
            // depth d, |step(d)| · c · smoothstep'(d / W) / (W · across metres)
            // (smoothstep' = 6u(1 − u), its largest over the pixel's span, 1.5 where the span
            // holds the band's middle), over the limit at this width. The added slope falls
            // about as 1 / W: scaled by that ratio, and again until it holds (a step rising
            // inwards is met as the band reaches it; a limit that falls as the band widens,
            // to its fixed point).
            std::vector<double> need(widths.size());
            f.capped = 0;
            for (std::size_t t = 0; t < widths.size(); ++t) {
                const double w = double(widths[t]);
                double added = 0.0;
                for (std::size_t d = 0; d < f.steps[t].size() && double(d) < w; ++d) {
                    if (f.steps[t][d] == 0.0f) continue;
                    const auto [column, row] = band.pixelAt(edge, static_cast<std::int64_t>(t),
                                                            static_cast<std::int64_t>(d));
                    if (band.relativeDistance(double(column) + 0.5, double(row) + 0.5).second !=
                        edge)
                        continue;
                    const double u0 = double(d) / w, u1 = std::min(1.0, double(d + 1) / w);
                    const double u = std::clamp(0.5, u0, u1);  // nearest the steepest
                    added = std::max(added, double(f.steps[t][d]) * 6.0 * u * (1.0 - u));
                }
                added *= f.factor[t] / (w * f.acrossMetres[t]);
                const double limit = source.slopeLimit(edge, w);
                double wanted = kMinimumPixels;
                if (added > 0.0)
                    wanted =
                        limit > 0.0 ? w * added / limit : std::numeric_limits<double>::infinity();
                f.capped += wanted > widest * (1.0 + 1e-6) ? 1 : 0;
                need[t] = std::clamp(wanted, kMinimumPixels, widest);
            }
            // Spread along the edge: the lowest profile over every need that falls by at most
            // kWidthChangePerPixel a pixel (a cone from each need: two passes).
            for (std::size_t t = 1; t < need.size(); ++t)
                need[t] = std::max(need[t], need[t - 1] - kWidthChangePerPixel);
            for (std::size_t t = need.size() - 1; t-- > 0;)
                need[t] = std::max(need[t], need[t + 1] - kWidthChangePerPixel);
            // Never narrower than before (the iteration only widens: it ends).
            for (std::size_t t = 0; t < need.size(); ++t) {
                const auto w = static_cast<float>(need[t]);
                if (w > widths[t] + 1e-3f) {
                    widths[t] = w;
                    changed = true;
                }
            }
        }
    }
    band.m_cappedPixels = 0;
    for (const EdgeFit& f : fits) band.m_cappedPixels += f.capped;
    return band;
}

double SeamBand::widthAt(SeamEdge edge, double t) const {
    const std::vector<float>& widths = m_widths[index(edge)];
    if (widths.empty()) return 0.0;
    const double last = static_cast<double>(widths.size() - 1);
    const double c = std::clamp(t, 0.0, last);
    const auto i = static_cast<std::size_t>(c);
    if (i + 1 >= widths.size()) return widths.back();
    const double f = c - static_cast<double>(i);
    return (1.0 - f) * double(widths[i]) + f * double(widths[i + 1]);
}

std::pair<double, std::optional<SeamEdge>> SeamBand::relativeDistance(double x, double y) const {
    double relative = std::numeric_limits<double>::infinity();
    std::optional<SeamEdge> governing;
    for (SeamEdge edge : kEdges) {
        if (!hasEdge(edge)) continue;
        double distance = 0.0, t = 0.0;
        switch (edge) {
            case SeamEdge::West:
                distance = x, t = y - 0.5;
                break;
            case SeamEdge::East:
                distance = double(m_width) - x, t = y - 0.5;
                break;
            case SeamEdge::North:
                distance = y, t = x - 0.5;
                break;
            case SeamEdge::South:
                distance = double(m_height) - y, t = x - 0.5;
                break;
        }
        const double r = distance / widthAt(edge, t);
        if (r < relative) relative = r, governing = edge;
    }
    return {relative, governing};
}

double SeamBand::weight(double x, double y) const {
    const double t = std::clamp(relativeDistance(x, y).first, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

std::optional<SeamEdge> SeamBand::governingEdge(double x, double y) const {
    return relativeDistance(x, y).second;
}

double SeamBand::narrowestPixels() const {
    double narrowest = std::numeric_limits<double>::infinity();
    for (const std::vector<float>& widths : m_widths)
        for (float w : widths) narrowest = std::min(narrowest, double(w));
    return std::isfinite(narrowest) ? narrowest : 0.0;
}

double SeamBand::widestPixels() const {
    double widest = 0.0;
    for (const std::vector<float>& widths : m_widths)
        for (float w : widths) widest = std::max(widest, double(w));
    return widest;
}

}  // namespace terrain::io
