// GlobeTour: grouping the local sources into places, their centres and the order flown.
#include "GlobeTour.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

namespace terrain::tools {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
/// Extents closer than this touch (tiles that share an edge, up to rounding), degrees.
constexpr double kTouchDeg = 1e-3;

// A longitude interval on the circle: from west, eastwards over span degrees (0 … 360).
struct LongitudeSpan {
    double west = -180.0, span = 360.0;
};

double eastwardsDeg(double from, double to) {  // 0 … 360
    const double d = std::fmod(to - from, 360.0);
    return d < 0.0 ? d + 360.0 : d;
}

LongitudeSpan spanOf(double west, double east) {
    // −180 … 180 and any box whose east meets its west the long way round: the whole circle.
    const double span = east >= west ? east - west : east + 360.0 - west;
    return {west, std::min(span, 360.0)};
}

bool holds(const LongitudeSpan& s, double longitudeDeg, double slackDeg) {
    return s.span >= 360.0 || eastwardsDeg(s.west, longitudeDeg) <= s.span + slackDeg ||
           eastwardsDeg(longitudeDeg, s.west) <= slackDeg;
}

bool overlap(const LongitudeSpan& a, const LongitudeSpan& b) {
    return holds(a, b.west, kTouchDeg) || holds(b, a.west, kTouchDeg);
}

// The shorter of the two spans that start at either's west and hold both (they overlap).
LongitudeSpan unite(const LongitudeSpan& a, const LongitudeSpan& b) {
    const LongitudeSpan fromA{a.west, std::max(a.span, eastwardsDeg(a.west, b.west) + b.span)};
    const LongitudeSpan fromB{b.west, std::max(b.span, eastwardsDeg(b.west, a.west) + a.span)};
    const LongitudeSpan& shorter = fromA.span <= fromB.span ? fromA : fromB;
    return shorter.span >= 360.0 ? LongitudeSpan{} : shorter;
}

// The centre as the flight has always gone to it: the middle latitude, and the middle of the
// longitude span wrapped to −180 … 180.
void centre(GlobeTourPlace& place) {
    const LongitudeSpan s = spanOf(place.west, place.east);
    place.latitudeDeg = 0.5 * (place.south + place.north);
    place.longitudeDeg = std::remainder(place.west + 0.5 * s.span, 360.0);
}

bool within(const io::ManifestGlobeSource& s, double latitudeDeg, double longitudeDeg) {
    return latitudeDeg >= s.south && latitudeDeg <= s.north &&
           holds(spanOf(s.west, s.east), longitudeDeg, 0.0);
}

double distanceRad(const GlobeTourPlace& a, const GlobeTourPlace& b) {
    const double phi1 = a.latitudeDeg * kDegree, phi2 = b.latitudeDeg * kDegree;
    const double dPhi = phi2 - phi1, dLambda = (b.longitudeDeg - a.longitudeDeg) * kDegree;
    const double h = std::pow(std::sin(dPhi / 2), 2) +
                     std::cos(phi1) * std::cos(phi2) * std::pow(std::sin(dLambda / 2), 2);
    return 2.0 * std::asin(std::min(1.0, std::sqrt(h)));  // haversine
}

// The sources (indices into `sources`, finest first) that touch or overlap, each set one place.
std::vector<std::vector<std::size_t>> touchingGroups(
    const std::vector<io::ManifestGlobeSource>& sources, const std::vector<std::size_t>& local) {
    std::vector<std::size_t> parent(local.size());
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    const auto root = [&](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (std::size_t i = 0; i < local.size(); ++i)
        for (std::size_t j = i + 1; j < local.size(); ++j) {
            const io::ManifestGlobeSource& a = sources[local[i]];
            const io::ManifestGlobeSource& b = sources[local[j]];
            if (a.south <= b.north + kTouchDeg && b.south <= a.north + kTouchDeg &&
                overlap(spanOf(a.west, a.east), spanOf(b.west, b.east)))
                parent[std::max(root(i), root(j))] = std::min(root(i), root(j));
        }
    std::vector<std::vector<std::size_t>> groups;
    std::vector<std::size_t> groupOfRoot(local.size(), std::numeric_limits<std::size_t>::max());
    for (std::size_t i = 0; i < local.size(); ++i) {  // in the sources' order: finest first
        std::size_t& g = groupOfRoot[root(i)];
        if (g == std::numeric_limits<std::size_t>::max()) {
            g = groups.size();
            groups.emplace_back();
        }
        groups[g].push_back(local[i]);
    }
    return groups;
}

GlobeTourPlace placeOf(const std::vector<io::ManifestGlobeSource>& sources,
                       const std::vector<std::size_t>& group) {
    const io::ManifestGlobeSource& finest = sources[group.front()];
    GlobeTourPlace place{.inputs = {},
                         .west = finest.west,
                         .south = finest.south,
                         .east = finest.east,
                         .north = finest.north};
    LongitudeSpan longitudes = spanOf(finest.west, finest.east);
    for (std::size_t k : group) {
        const io::ManifestGlobeSource& s = sources[k];
        place.inputs.push_back(s.input);
        if (k == group.front()) continue;
        place.south = std::min(place.south, s.south);
        place.north = std::max(place.north, s.north);
        longitudes = unite(longitudes, spanOf(s.west, s.east));
    }
    if (group.size() > 1) {  // a source's own numbers stay as they are
        place.west = longitudes.span >= 360.0 ? -180.0 : std::remainder(longitudes.west, 360.0);
        place.east = longitudes.span >= 360.0
                         ? 180.0
                         : std::remainder(longitudes.west + longitudes.span, 360.0);
    }
    centre(place);
    const bool shown = std::any_of(group.begin(), group.end(), [&](std::size_t k) {
        return within(sources[k], place.latitudeDeg, place.longitudeDeg);
    });
    if (!shown) {  // an L of tiles: its box's centre lies beside them
        GlobeTourPlace own{.inputs = {},
                           .west = finest.west,
                           .south = finest.south,
                           .east = finest.east,
                           .north = finest.north};
        centre(own);
        place.latitudeDeg = own.latitudeDeg;
        place.longitudeDeg = own.longitudeDeg;
    }
    return place;
}

}  // namespace

double extentShareOfEarth(double west, double south, double east, double north) {
    const double band = 0.5 * (std::sin(std::clamp(north, -90.0, 90.0) * kDegree) -
                               std::sin(std::clamp(south, -90.0, 90.0) * kDegree));
    return std::max(0.0, band) * spanOf(west, east).span / 360.0;
}

GlobeTourPlan planGlobeTour(const io::ManifestGlobe& globe) {
    GlobeTourPlan plan;
    plan.perSource = !globe.sources.empty();
    std::vector<std::size_t> local;
    for (std::size_t k = 0; k < globe.sources.size(); ++k) {
        const io::ManifestGlobeSource& s = globe.sources[k];
        if (extentShareOfEarth(s.west, s.south, s.east, s.north) >= kGlobalShare)
            plan.global.push_back(s.input);
        else
            local.push_back(k);
    }
    if (local.empty()) {
        // Nothing but global grids (or no record of the sources): the one extent, the finest
        // source's, as the flight went before it knew the others.
        GlobeTourPlace only{.inputs = {},
                            .west = globe.west,
                            .south = globe.south,
                            .east = globe.east,
                            .north = globe.north};
        if (!globe.sources.empty()) only.inputs.push_back(globe.sources.front().input);
        centre(only);
        plan.places.push_back(std::move(only));
        return plan;
    }
    std::vector<GlobeTourPlace> places;
    for (const std::vector<std::size_t>& group : touchingGroups(globe.sources, local))
        places.push_back(placeOf(globe.sources, group));
    // From the place of the finest local source, each time to the nearest not yet visited: a
    // short tour for the few places a composite has.
    std::vector<bool> visited(places.size(), false);
    std::size_t at = 0;
    for (std::size_t step = 0; step < places.size(); ++step) {
        visited[at] = true;
        plan.places.push_back(places[at]);
        std::size_t next = at;
        double nearest = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < places.size(); ++j)
            if (!visited[j] && distanceRad(places[at], places[j]) < nearest) {
                nearest = distanceRad(places[at], places[j]);
                next = j;
            }
        at = next;
    }
    return plan;
}

}  // namespace terrain::tools
