// GlobeFlags: the flags of a flight over a globe pyramid, declared once: a fixed pose (--lat,
// --lon, --altitude, --heading, --pitch), --no-horizon-culling and --visit (one place of the
// default flight). A planar pyramid refuses them by name (SurfaceKit::refuseForeignFlags).
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace terrain::tools {

struct GlobeFlags {
    // A fixed pose where any of these is given (the data's centre for the others, 20,000 km
    // up); else the program's flight.
    std::optional<double> latitudeDeg, longitudeDeg, heightM;
    double headingDeg = 0.0;
    double pitchDeg = -90.0;
    bool noHorizonCulling = false;
    /// The one place of the default flight to fly to (1 = its first; the program lists them),
    /// or the place whose centre a fixed pose defaults to; else every place in turn.
    std::optional<int> visit;

    /// Adds --visit alone, bound to `visit` (a program with no other globe flag).
    void addVisitTo(CLI::App& app) {
        // No range check here: the flight plan (globeFlightPlan) refuses a place the tour
        // lacks, 0 and negative ones included, naming the pyramid and its places (CLI11's
        // check printed its own range, 0 to DBL_MAX in full, and exited 105).
        m_options.push_back(
            app.add_option("--visit", visit,
                           "Globe pyramids: fly to place N of the default flight only (1: the "
                           "first; the program prints the places, one per local source)"));
    }

    /// Adds the flags, bound to these members (the defaults shown).
    void addTo(CLI::App& app) {
        m_options = {
            app.add_option("--lat", latitudeDeg,
                           "Globe pyramids: camera latitude, degrees (a fixed pose)")
                ->check(CLI::Range(-90.0, 90.0)),
            app.add_option("--lon", longitudeDeg, "Globe pyramids: camera longitude, degrees")
                ->check(CLI::Range(-360.0, 360.0)),
            app.add_option("--altitude", heightM,
                           "Globe pyramids: camera height above the WGS84 ellipsoid, metres"),
            app.add_option("--heading", headingDeg, "Globe pyramids: degrees clockwise from north")
                ->capture_default_str(),
            app.add_option("--pitch", pitchDeg,
                           "Globe pyramids: degrees above the horizon (-90: down)")
                ->capture_default_str()
                ->check(CLI::Range(-90.0, 90.0)),
            app.add_flag("--no-horizon-culling", noHorizonCulling,
                         "Globe pyramids: draw patches behind the horizon too (for comparison)"),
        };
        addVisitTo(app);
    }

    /// Whether --lat, --lon or --altitude asks for a fixed pose.
    bool fixedPose() const { return latitudeDeg || longitudeDeg || heightM; }

    /// The flags the command line gave ("--lat", "--pitch"), in the order addTo declares them;
    /// asks the app addTo was given, which must still live.
    std::vector<std::string> given() const {
        std::vector<std::string> names;
        for (const CLI::Option* option : m_options)
            if (option->count() > 0) names.push_back(option->get_name());
        return names;
    }

private:
    std::vector<CLI::Option*> m_options;
};

}  // namespace terrain::tools
