// ChartScript: finds and runs the chart tool (tools/charts/terrain_charts.py) with Debian's
// /usr/bin/python3, whose python3-matplotlib it needs, for terrain-bench --report.
#pragma once

#include "terrain/base/Result.h"

#include <filesystem>
#include <string>
#include <vector>

namespace terrain::tools {

struct ChartScript {
    std::filesystem::path python;  ///< TERRAIN_PYTHON, else /usr/bin/python3, else python3
    std::filesystem::path script;
};

/// TERRAIN_CHARTS_SCRIPT if set; else the source tree's copy (a build tree's program);
/// else the installed copy, <prefix>/share/terrain/charts next to <prefix>/bin. An Error
/// names every place looked at.
Result<ChartScript> findChartScript(const std::filesystem::path& executable);

/// Runs `python script args...` (no shell) and waits; an Error when it cannot start or
/// exits non-zero (its own message went to stderr).
Status runChartScript(const ChartScript& chart, const std::vector<std::string>& args);

}  // namespace terrain::tools
