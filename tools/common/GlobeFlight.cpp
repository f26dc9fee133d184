#include "GlobeFlight.h"

#include "terrain/pyramid/GlobeGroundHeight.h"

#include <cmath>

namespace terrain::tools {

Result<GlobeFlightTarget> globeFlightTarget(const std::filesystem::path& pyramid) {
    auto query = io::GlobeGroundQuery::open(pyramid);
    if (!query) return query.error();
    const std::optional<io::ManifestGlobe>& g = query.value().reader().manifest().globe;
    // The extent's centre; west > east means it crosses the antimeridian.
    const double span = g->east >= g->west ? g->east - g->west : g->east + 360.0 - g->west;
    GlobeFlightTarget target;
    target.latitudeDeg = 0.5 * (g->south + g->north);
    target.longitudeDeg = std::remainder(g->west + 0.5 * span, 360.0);
    auto ground = query.value().at(target.latitudeDeg, target.longitudeDeg);
    if (!ground) return ground.error();
    target.groundM = ground.value().heightM;
    target.groundLevel = ground.value().faceLevel;
    return target;
}

Result<runtime::GlobeCameraPath> globeFlight(const std::filesystem::path& pyramid,
                                             const std::string& pathFile, double durationS,
                                             double clearanceM) {
    if (!pathFile.empty()) return runtime::GlobeCameraPath::load(pathFile);
    auto target = globeFlightTarget(pyramid);
    if (!target) return target.error();
    return runtime::GlobeCameraPath::fromOrbit(target.value().latitudeDeg,
                                               target.value().longitudeDeg,
                                               target.value().groundM + clearanceM, durationS);
}

}  // namespace terrain::tools
