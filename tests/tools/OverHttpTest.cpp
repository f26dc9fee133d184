// The programs on a pyramid at an http:// URL (issue 49), served by a real nginx behind a
// fault proxy the test owns (tests/support/FaultProxy.h):
//  - terrain-stress flies its tiny-budget flight while the network resets, drops, answers
//    503, cuts bodies short and trickles them, and every invariant holds (never a hole, no
//    leaked layer, requests accounted for); the faults were met, and retried; no file's body
//    came twice, though every reader thread opened every file;
//  - the same flight again, the disk cache kept: no body crosses the network and every file
//    comes from the cache (the "cache hit rate on a repeated flight ≥ 99 %");
//  - terrain-render --settle draws the same frames over HTTP as from the folder: the same
//    triangles and patches, frame by frame.
#include "FaultProxy.h"
#include "NginxServer.h"
#include "TempFolder.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace terrain {
namespace {

namespace fs = std::filesystem;
using test::FaultPlan;
using test::FaultProxy;
using test::NginxServer;
using test::ProxyFault;
using test::TempFolder;

struct ToolRun {
    int status = -1;
    std::string out;  // stdout
    std::string err;  // stderr
};

// Runs `command` (a shell line) with `environment` set for it, stdout and stderr apart.
ToolRun runTool(const std::string& command, const std::string& environment,
                const fs::path& errFile) {
    ToolRun run;
    FILE* pipe = ::popen((environment + " " + command + " 2>" + errFile.string()).c_str(), "r");
    if (pipe == nullptr) return run;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        run.out.append(buffer, n);
    const int status = ::pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream err(errFile);
    run.err.assign(std::istreambuf_iterator<char>(err), {});
    return run;
}

nlohmann::json jsonOf(const ToolRun& run) {
    nlohmann::json j = nlohmann::json::parse(run.out, nullptr, false);
    return j.is_discarded() ? nlohmann::json::object() : j;
}

// The rows of a telemetry CSV: column name → values, frame by frame.
std::vector<std::vector<std::string>> csvRows(const fs::path& file) {
    std::vector<std::vector<std::string>> rows;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> fields;
        std::stringstream cells(line);
        for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
        rows.push_back(std::move(fields));
    }
    return rows;
}

std::vector<std::string> column(const std::vector<std::vector<std::string>>& rows,
                                const std::string& name) {
    std::vector<std::string> values;
    if (rows.empty()) return values;
    const auto at = std::find(rows[0].begin(), rows[0].end(), name);
    if (at == rows[0].end()) return values;
    const auto index = static_cast<std::size_t>(at - rows[0].begin());
    for (std::size_t r = 1; r < rows.size(); ++r)
        values.push_back(index < rows[r].size() ? rows[r][index] : "");
    return values;
}

class OverHttp : public ::testing::Test {
protected:
    void SetUp() override {
        TERRAIN_NGINX_OR_SKIP(server);
        ASSERT_TRUE(proxy.ready());
        ASSERT_TRUE(fs::exists(fs::path(TERRAIN_TOOLS_OUT) / "stress.pyramid" / "manifest.json"))
            << "the stress_pyramid fixture did not run";
    }
    // The environment of a run: this test's own disk cache, short retry waits.
    std::string environment() const {
        return "TERRAIN_CACHE_DIR=" + cache.path().string() + " TERRAIN_HTTP_TIMEOUT=20";
    }

    TempFolder cache;
    TempFolder work;
    NginxServer server{TERRAIN_TOOLS_OUT};
    FaultProxy proxy{server.port()};
};

TEST_F(OverHttp, StressInvariantsHoldWithNetworkFaultsThenTheCacheServesARepeatedFlight) {
    // Shards whole (TERRAIN_HTTP_RANGE_BYTES=0), so that what a flight reads is whole files
    // whatever the reader threads' timing, and the repeated flight reads nothing new; shards
    // read by ranges under faults are RenderDrawsTheSameFramesAsFromTheFolder's.
    const std::string url = proxy.url("stress.pyramid");
    const std::string wholeShards = environment() + " TERRAIN_HTTP_RANGE_BYTES=0";
    const std::string stress = std::string(TERRAIN_STRESS) + " " + url +
                               " --duration-s 12 --gpu-layers 24 --cpu-cache-mib 0.5"
                               " --upload-mib-per-frame 0.05 --error-px 1 --seed 3 --json";
    // The first request for each file faulted, the five kinds in turn (the pyramid has six
    // files, all of which the flight reads), and 2 ms before every answer.
    proxy.setPlan(FaultPlan{.latency = std::chrono::milliseconds(2), .faultEvery = 1});
    const ToolRun faulty = runTool(stress, wholeShards, work.path() / "stress1.err");
    ASSERT_EQ(faulty.status, 0) << faulty.err;
    const nlohmann::json first = jsonOf(faulty);
    ASSERT_TRUE(first.contains("invariant_violations")) << faulty.out << faulty.err;
    EXPECT_EQ(first["invariant_violations"], 0) << first["violations"].dump(1);
    for (ProxyFault kind : FaultPlan{}.kinds)
        EXPECT_GE(proxy.faulted(kind), 1) << "fault " << static_cast<int>(kind) << " never met in "
                                          << proxy.requests() << " requests";
    const nlohmann::json& http1 = first["telemetry"]["http"];
    // Each file came once, though every reader thread opened it: the readers that wanted a
    // file at once waited for one fetch (request coalescing through the cache's entry locks).
    int files = 0;
    for (const auto& entry :
         fs::recursive_directory_iterator(fs::path(TERRAIN_TOOLS_OUT) / "stress.pyramid"))
        files += entry.is_regular_file() ? 1 : 0;
    EXPECT_GT(http1["files_fetched"].get<int>(), 1) << http1.dump();
    EXPECT_LE(http1["files_fetched"].get<int>(), files) << http1.dump();
    EXPECT_GE(http1["retries"].get<int>(), 1) << http1.dump();
    EXPECT_GT(http1["fetched_bytes"].get<std::uint64_t>(), 0u);

    // The same flight again, the network sound: every file from the cache, no body fetched.
    proxy.setPlan(FaultPlan{.latency = std::chrono::milliseconds(2)});
    const ToolRun again = runTool(stress, wholeShards, work.path() / "stress2.err");
    ASSERT_EQ(again.status, 0) << again.err;
    const nlohmann::json second = jsonOf(again);
    EXPECT_EQ(second["invariant_violations"], 0) << second["violations"].dump(1);
    const nlohmann::json& http2 = second["telemetry"]["http"];
    EXPECT_EQ(http2["fetched_bytes"], 0) << http2.dump();
    EXPECT_EQ(http2["files_fetched"], 0) << http2.dump();
    EXPECT_GE(http2["cache_hit_rate"].get<double>(), 0.99) << http2.dump();
}

TEST_F(OverHttp, RenderDrawsTheSameFramesAsFromTheFolder) {
    // Its finest shard (1.6 MB) is read by ranges, each request faulted once.
    const fs::path local = fs::path(TERRAIN_TOOLS_OUT) / "stress.pyramid";
    const std::string flags = " --settle --frames 8 --every 0 --width 160 --height 120 --json";
    proxy.setPlan(FaultPlan{.faultEvery = 1});  // retried faults must not change a frame
    const ToolRun there = runTool(std::string(TERRAIN_RENDER) + " " + proxy.url("stress.pyramid") +
                                      " -o " + (work.path() / "remote").string() + flags,
                                  environment(), work.path() / "render1.err");
    ASSERT_EQ(there.status, 0) << there.err;
    const ToolRun here = runTool(std::string(TERRAIN_RENDER) + " " + local.string() + " -o " +
                                     (work.path() / "local").string() + flags,
                                 environment(), work.path() / "render2.err");
    ASSERT_EQ(here.status, 0) << here.err;
    const auto remoteRows = csvRows(work.path() / "remote" / "telemetry.csv");
    const auto localRows = csvRows(work.path() / "local" / "telemetry.csv");
    ASSERT_EQ(remoteRows.size(), 9u) << "a header and 8 frames";
    for (const char* name : {"triangles", "patches_drawn", "patches_culled"}) {
        const std::vector<std::string> a = column(remoteRows, name), b = column(localRows, name);
        ASSERT_EQ(a.size(), 8u) << name;
        EXPECT_EQ(a, b) << name;
    }
    const nlohmann::json remote = jsonOf(there)["telemetry"], folder = jsonOf(here)["telemetry"];
    EXPECT_GT(remote["http"]["files_fetched"].get<int>(), 0);
    EXPECT_EQ(folder["http"]["requests"], 0);
    // The payloads the view needed, read from the files either way; over HTTP the files or
    // ranges holding them came, so at least as many bytes crossed the network.
    EXPECT_GT(remote["totals"]["stored_bytes_read"].get<std::uint64_t>(), 0u);
    EXPECT_GT(folder["totals"]["stored_bytes_read"].get<std::uint64_t>(), 0u);
    EXPECT_GE(remote["http"]["fetched_per_needed_byte"].get<double>(), 1.0) << remote.dump();
    EXPECT_TRUE(folder["http"]["fetched_per_needed_byte"].is_null());
}

}  // namespace
}  // namespace terrain
