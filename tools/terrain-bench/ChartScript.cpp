// ChartScript: the chart tool located by environment, source tree or install prefix, and
// run with fork/exec so arguments never pass through a shell.
#include "ChartScript.h"

#include <fmt/format.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace terrain::tools {

Result<ChartScript> findChartScript(const std::filesystem::path& executable) {
    namespace fs = std::filesystem;
    ChartScript chart;
    if (const char* python = std::getenv("TERRAIN_PYTHON")) {
        chart.python = python;
    } else {
        // Debian's interpreter: the one that sees python3-matplotlib (a pyenv python3 on
        // PATH does not).
        chart.python =
            fs::exists("/usr/bin/python3") ? fs::path("/usr/bin/python3") : fs::path("python3");
    }
    std::vector<fs::path> candidates;
    if (const char* script = std::getenv("TERRAIN_CHARTS_SCRIPT")) candidates.emplace_back(script);
    candidates.emplace_back(TERRAIN_CHARTS_SOURCE_SCRIPT);
    std::error_code ec;
    const fs::path self = fs::canonical(executable, ec);
    if (!ec)
        candidates.push_back(self.parent_path().parent_path() / "share" / "terrain" / "charts" /
                             "terrain_charts.py");
    std::string looked;
    for (const fs::path& candidate : candidates) {
        if (fs::is_regular_file(candidate, ec)) {
            chart.script = candidate;
            return chart;
        }
        looked += (looked.empty() ? "" : ", ") + candidate.string();
    }
    return Error{"the chart tool terrain_charts.py is not in " + looked +
                 " (set TERRAIN_CHARTS_SCRIPT)"};
}

Status runChartScript(const ChartScript& chart, const std::vector<std::string>& args) {
    std::vector<std::string> argv{chart.python.string(), chart.script.string()};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> pointers;
    for (std::string& a : argv) pointers.push_back(a.data());
    pointers.push_back(nullptr);
    const pid_t child = fork();
    if (child < 0)
        return Error{
            fmt::format("{}: cannot start: {}", chart.script.string(), std::strerror(errno))};
    if (child == 0) {
        execvp(pointers[0], pointers.data());
        std::fprintf(stderr, "terrain-bench: cannot run %s: %s\n", pointers[0],
                     std::strerror(errno));
        _exit(127);
    }
    int status = 0;
    while (waitpid(child, &status, 0) < 0) {
        if (errno != EINTR)
            return Error{
                fmt::format("{}: waitpid failed: {}", chart.script.string(), std::strerror(errno))};
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        return Error{fmt::format("{} {} failed (exit status {}); see its message above",
                                 chart.python.string(), chart.script.string(),
                                 WIFEXITED(status) ? WEXITSTATUS(status) : -1)};
    }
    return {};
}

}  // namespace terrain::tools
