// GlobeTour: the places the default flight over a globe pyramid visits, chosen from the
// manifest's sources (docs/terrain-render.md, "The default flight"): every local source in
// turn, tiles that touch or overlap as one place, from the finest source on by the nearest
// next; a global grid (one covering half the Earth or more) is flown over, not visited. A
// manifest that records no source's extent (built before it did) gives its one extent, the
// finest source's. Pure: no I/O, any thread.
#pragma once

#include "terrain/pyramid/PyramidManifest.h"

#include <string>
#include <vector>

namespace terrain::tools {

struct GlobeTourPlace {
    /// The sources it shows, finest first (empty where the manifest names none).
    std::vector<std::string> inputs;
    double west = -180.0, south = -90.0, east = 180.0, north = 90.0;  ///< their extent, degrees
    /// Where the flight goes down: the extent's centre (the finest source's centre where that
    /// falls outside every source of the place).
    double latitudeDeg = 0.0, longitudeDeg = 0.0;
};

struct GlobeTourPlan {
    std::vector<GlobeTourPlace> places;  ///< in the order flown; at least one
    std::vector<std::string> global;     ///< sources covering half the Earth or more
    /// Whether the manifest records each source's extent (ManifestGlobe::sources); else the
    /// one place is its sourceExtent.
    bool perSource = false;
};

/// The share of the Earth's surface (of a sphere) a [west, south, east, north] box covers,
/// 0 … 1; west > east crosses the antimeridian.
double extentShareOfEarth(double west, double south, double east, double north);

/// A global grid: a source covering at least this share of the Earth.
inline constexpr double kGlobalShare = 0.5;

/// The tour over `globe`'s sources.
GlobeTourPlan planGlobeTour(const io::ManifestGlobe& globe);

}  // namespace terrain::tools
