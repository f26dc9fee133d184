// SeamsInView: each looked-at pixel unprojected to the ECEF point it draws, that point to
// latitude and longitude, and its distance to each seam's extent edge measured on the
// ellipsoid's local metric (metres of a degree at that latitude), which is ample for
// deciding whether a band several source pixels wide is in view.
#include "SeamsInView.h"

#include "terrain/globe/Wgs84.h"
#include "terrain/runtime/ScreenProjection.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace terrain::tools {
namespace {

struct SeamBand {
    const io::ManifestSeam* seam = nullptr;
    io::ManifestGlobeSource extent;
};

/// Metres of one degree of latitude and of longitude at `latitudeDeg` (WGS84).
std::pair<double, double> metresPerDegree(double latitudeDeg) {
    const globe::CurvatureRadii r = globe::Wgs84::curvatureRadiiAt(latitudeDeg);
    const double perDegree = std::numbers::pi / 180.0;
    return {r.meridian * perDegree,
            r.primeVertical * std::cos(latitudeDeg * perDegree) * perDegree};
}

/// Whether (lat, lon) lies inside `e` within `bandM` of its edge.
bool inBand(const io::ManifestGlobeSource& e, double lat, double lon, double bandM) {
    if (lat < e.south || lat > e.north) return false;
    const double width = e.east > e.west ? e.east - e.west : e.east - e.west + 360.0;
    const double u = std::fmod(lon - e.west + 720.0, 360.0);
    if (u > width) return false;
    const auto [northM, eastM] = metresPerDegree(lat);
    // A source around the whole Earth has no east or west edge.
    const double alongLongitude =
        width >= 360.0 ? std::numeric_limits<double>::infinity() : std::min(u, width - u) * eastM;
    const double alongLatitude = std::min(lat - e.south, e.north - lat) * northM;
    return std::min(alongLongitude, alongLatitude) <= bandM;
}

}  // namespace

SeamsSeen seamsInView(const io::PyramidManifest& manifest, const runtime::Camera& camera,
                      std::span<const float> depth, int stridePx) {
    SeamsSeen seen;
    if (!manifest.globe) return seen;
    std::vector<SeamBand> bands;
    for (const io::ManifestSeam& seam : manifest.globe->seams) {
        const auto source =
            std::find_if(manifest.globe->sources.begin(), manifest.globe->sources.end(),
                         [&](const io::ManifestGlobeSource& s) { return s.input == seam.input; });
        if (source != manifest.globe->sources.end()) bands.push_back({&seam, *source});
    }
    if (bands.empty()) return seen;
    std::vector<bool> inView(bands.size(), false);
    const glm::dmat4 inverse = glm::inverse(camera.relativeViewProjection());
    const int w = camera.viewportWidth, h = camera.viewportHeight;
    for (int y = 0; y < h; y += stridePx) {
        for (int x = 0; x < w; x += stridePx) {
            const float d = depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x)];
            if (!(d > 0.0f)) continue;
            const glm::dvec3 world =
                camera.position + runtime::unprojectPixel(inverse, w, h, x, y, d);
            const globe::Geodetic g = globe::Wgs84::toGeodetic(world);
            for (std::size_t k = 0; k < bands.size(); ++k)
                if (!inView[k] && inBand(bands[k].extent, g.latitudeDeg, g.longitudeDeg,
                                         bands[k].seam->bandMetres[1]))
                    inView[k] = true;
        }
    }
    for (std::size_t k = 0; k < bands.size(); ++k) {
        if (!inView[k]) continue;
        ++seen.seams;
        const io::ManifestSeam& s = *bands[k].seam;
        if (std::isnan(seen.seamSlope) || s.seamSlope > seen.seamSlope) {
            seen.seamSlope = s.seamSlope;
            seen.sourceSlopeP99 = s.sourceSlopeP99;
        }
    }
    return seen;
}

}  // namespace terrain::tools
