// GlobeKit: the globe's flight, which SurfaceKit's globe side flies (GlobeKit.cpp) and
// terrain-bench too: the default flight from 20,000 km down to `clearanceM` above the ground
// at each place of the data in turn (GlobeTour: every local source, the finest's first; the
// ground read from the pyramid's finest patch there, io::GlobeGroundQuery), or at the one place
// --visit picks.
#pragma once

#include "GlobeTour.h"

#include "terrain/base/Result.h"
#include "terrain/runtime/GlobeCameraPath.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace terrain::tools {

/// A place the flight goes down to and the ground there.
struct GlobeFlightStop {
    GlobeTourPlace place;
    double groundM = 0.0;  ///< the drawn ground there, above the ellipsoid
    int groundLevel = -1;  ///< the face level it was read at; −1: no data there
};

struct GlobeFlightPlan {
    GlobeTourPlan tour;                  ///< every place the default flight visits
    std::vector<GlobeFlightStop> stops;  ///< the places flown: the tour's, or the one picked
    std::optional<int> visit;            ///< the place picked (1 = the tour's first), if any
    std::size_t inputCount = 0;          ///< the pyramid's source.inputs
};

/// The clearance of the default flight's end above the ground.
inline constexpr double kArrivalClearanceM = 1.0;

/// The tour over `pyramid`'s sources and the ground at each place; `visit` keeps its place
/// only. Errors name the pyramid (and a --visit beyond the tour's places).
Result<GlobeFlightPlan> globeFlightPlan(const std::filesystem::path& pyramid,
                                        std::optional<int> visit = std::nullopt);

/// GlobeCameraPath::fromTour over the plan's stops, `durationS` long, arriving `clearanceM`
/// above the ground at each.
runtime::GlobeCameraPath globeTourFlight(const GlobeFlightPlan& plan, double durationS,
                                         double clearanceM = kArrivalClearanceM);

/// What the program says of the plan, one line: the places flown (their sources and where),
/// the global grids flown over, and how to pick one place (--visit N) or all of them.
std::string describeFlightPlan(const GlobeFlightPlan& plan, double durationS);

/// The report's fields of the plan: "flight_visits" (each place flown: its sources, where the
/// flight goes down, the ground there, when it arrives), "flight_passes_over" (the global grids),
/// "flight_places" (how many the tour has) and "flight_visit" (the place --visit picked, or
/// null).
nlohmann::json flightPlanJson(const GlobeFlightPlan& plan, double durationS);

}  // namespace terrain::tools
