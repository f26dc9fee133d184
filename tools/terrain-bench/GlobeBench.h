// GlobeBench: terrain-bench on a globe pyramid (docs/globe.md, "Figures"): the flight (a globe
// camera path, or from orbit, 20,000 km, down to 1 m above the data) at each threshold, every
// settled frame measured against the sources' full-resolution surface (a GlobeTruth) and,
// apart, against the pyramid's finest level (the LOD's own error, without the finest level's
// resampling of the sources, which no LOD can go below once the camera is close), triangles,
// patches, LOD time and the horizon-culled share per frame; the same flight without horizon culling
// for comparison; the time to full detail after arriving; the patches the same view needs at a
// pole, on the equator and over a cube corner; and the samples the pyramid stores against a
// longitude/latitude grid of the same equatorial spacing. Writes globe-bench.json, and with
// --report the charts by height and report.md (tools/charts/terrain_charts.py --globe-bench).
#pragma once

#include "ChartScript.h"
#include "StreamingBudgetFlags.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"

#include <optional>
#include <string>
#include <vector>

namespace terrain::tools {

struct GlobeBenchOptions {
    std::string pyramid;
    std::vector<std::string> sources;  ///< the DEMs it was built from (the truth)
    std::string pathFile;  ///< a globe camera path; empty: from orbit to 1 m above the data
    io::DemOpenOptions sourceOptions;  ///< how to read them (terrain-build's flags)
    std::vector<double> thresholdsPx;
    int frames = 48;
    int widthPx = 640;
    int heightPx = 360;
    std::string outputDir;
    double tolerancePx = 0.05;
    StreamingBudgets budgets;
    bool json = false;
    std::string commandLine;
    /// --report: the chart tool run on globe-bench.json, writing its charts and report.md here.
    std::string reportDir;
    std::optional<ChartScript> chart;
};

/// Runs the globe benchmark; the exit status.
int runGlobeBench(const GlobeBenchOptions& options);

}  // namespace terrain::tools
