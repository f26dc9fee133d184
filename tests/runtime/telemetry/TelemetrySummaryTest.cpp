// TelemetrySummary: totals, peaks, duration, throughput, hit rate and percentiles of a run,
// nulls where nothing was measured, and the exact set of user-facing JSON keys.
#include "terrain/runtime/TelemetrySummary.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace terrain::runtime {
namespace {

using nlohmann::json;

// Every key of toJson(), nested ones as "parent.key": the user-facing names, spelled out
// so that a rename or removal fails here.
const std::set<std::string> kExpectedKeys = {
    "frames",
    "duration_s",
    "throughput_tiles_per_s",
    "totals",
    "totals.requests_made",
    "totals.requests_cancelled",
    "totals.requests_completed",
    "totals.requests_failed",
    "totals.cpu_cache_hits",
    "totals.cpu_cache_misses",
    "totals.cpu_cache_hit_rate",
    "totals.cpu_cache_evictions",
    "totals.gpu_evictions",
    "totals.gpu_uploads",
    "totals.gpu_upload_bytes",
    "totals.gpu_uploads_deferred",
    "totals.disk_read_bytes",
    "totals.stored_bytes_read",
    "totals.faults",
    "peaks",
    "peaks.queue_depth",
    "peaks.cpu_cache_bytes",
    "peaks.gpu_layers_used",
    "frame_ms",
    "frame_ms.p50",
    "frame_ms.p95",
    "frame_ms.p99",
    "frame_ms.max",
    "load_latency_ms",
    "load_latency_ms.count",
    "load_latency_ms.p50",
    "load_latency_ms.p95",
    "load_latency_ms.p99",
    "load_latency_ms.max",
    "load_latency_ms.mean",
    "http",
    "http.requests",
    "http.retries",
    "http.files_fetched",
    "http.fetched_bytes",
    "http.not_modified",
    "http.cache_hits",
    "http.stale_served",
    "http.cache_hit_rate",
    "http.fetched_per_needed_byte",
    "imagery",
    "imagery.totals",
    "imagery.totals.requests_made",
    "imagery.totals.requests_cancelled",
    "imagery.totals.requests_completed",
    "imagery.totals.requests_failed",
    "imagery.totals.gpu_uploads",
    "imagery.totals.gpu_upload_bytes",
    "imagery.totals.gpu_evictions",
    "imagery.totals.faults",
    "imagery.peaks",
    "imagery.peaks.tiles_resident",
    "imagery.peaks.gpu_bytes",
    "imagery.peaks.cpu_cache_bytes",
};

void collectKeys(const json& object, const std::string& prefix, std::set<std::string>& keys) {
    for (const auto& [key, value] : object.items()) {
        keys.insert(prefix + key);
        if (value.is_object()) collectKeys(value, prefix + key + ".", keys);
    }
}

// The summary's percentile keys and the p each stands for.
constexpr std::pair<const char*, double> kPercentiles[] = {
    {"p50", 50.0}, {"p95", 95.0}, {"p99", 99.0}};

double exactPercentile(std::vector<double> values, double p) {
    std::sort(values.begin(), values.end());
    const double n = static_cast<double>(values.size());
    const auto rank = static_cast<std::size_t>(std::clamp(std::ceil(p * n / 100.0), 1.0, n));
    return values[rank - 1];
}

TEST(TelemetrySummary, KeysAreTheDocumentedOnes) {
    std::set<std::string> keys;
    collectKeys(TelemetrySummary().toJson(), "", keys);
    EXPECT_EQ(keys, kExpectedKeys);

    std::ifstream in(std::filesystem::path(TERRAIN_SOURCE_DIR) / "docs" / "telemetry.md");
    std::ostringstream docs;
    docs << in.rdbuf();
    ASSERT_FALSE(docs.str().empty()) << "docs/telemetry.md is missing";
    for (const std::string& key : kExpectedKeys) {
        const std::string leaf = key.substr(key.rfind('.') + 1);
        EXPECT_NE(docs.str().find("`" + leaf + "`"), std::string::npos)
            << key << " is not described in docs/telemetry.md";
    }
}

TEST(TelemetrySummary, EmptySummaryHasZerosAndNulls) {
    const TelemetrySummary summary;
    const json j = summary.toJson();
    EXPECT_EQ(j["frames"], 0);
    EXPECT_EQ(j["duration_s"], 0.0);
    EXPECT_TRUE(j["throughput_tiles_per_s"].is_null());
    EXPECT_EQ(j["totals"]["requests_made"], 0);
    EXPECT_EQ(j["totals"]["faults"], 0);
    EXPECT_TRUE(j["totals"]["cpu_cache_hit_rate"].is_null());
    EXPECT_TRUE(j["http"]["cache_hit_rate"].is_null());  // a folder: no file over HTTP
    EXPECT_TRUE(j["http"]["fetched_per_needed_byte"].is_null());
    EXPECT_EQ(j["peaks"]["queue_depth"], 0);
    for (const char* key : {"p50", "p95", "p99", "max"}) {
        EXPECT_TRUE(j["frame_ms"][key].is_null()) << key;
    }
    EXPECT_EQ(j["load_latency_ms"]["count"], 0);
    for (const char* key : {"p50", "p95", "p99", "max", "mean"}) {
        EXPECT_TRUE(j["load_latency_ms"][key].is_null()) << key;
    }
    // The whole object serialises (no NaN or infinity left for the dump to choke on).
    EXPECT_NO_THROW((void)j.dump());
}

TEST(TelemetrySummary, HttpCountsAreSummedAndTheCacheHitRateIsFilesFromTheCache) {
    TelemetrySummary summary;
    FrameTelemetry first;
    first.frameMs = 16.0;
    first.timeS = 1.0;
    first.httpRequests = 5;
    first.httpRetries = 1;
    first.httpFetched = 3;
    first.httpFetchedBytes = 3000;
    first.httpNotModified = 1;
    first.storedBytesRead = 1200;
    FrameTelemetry second = first;
    second.timeS = 2.0;
    second.httpFetched = 0;
    second.httpFetchedBytes = 0;
    second.httpRetries = 0;
    second.httpRequests = 2;
    second.httpNotModified = 2;
    second.httpCacheHits = 3;
    second.httpStaleServed = 1;
    second.storedBytesRead = 300;
    summary.add(first);
    summary.add(second);
    const json j = summary.toJson();
    EXPECT_EQ(j["http"]["requests"], 7);
    EXPECT_EQ(j["http"]["retries"], 1);
    EXPECT_EQ(j["http"]["files_fetched"], 3);
    EXPECT_EQ(j["http"]["fetched_bytes"], 3000);
    EXPECT_EQ(j["http"]["not_modified"], 3);
    EXPECT_EQ(j["http"]["cache_hits"], 3);
    EXPECT_EQ(j["http"]["stale_served"], 1);
    // 3 confirmed + 3 hits + 1 stale from the cache, of 10 files used.
    EXPECT_DOUBLE_EQ(j["http"]["cache_hit_rate"].get<double>(), 0.7);
    // 3000 bytes fetched for the 1500 the reads needed of the files.
    EXPECT_EQ(j["totals"]["stored_bytes_read"], 1500);
    EXPECT_DOUBLE_EQ(j["http"]["fetched_per_needed_byte"].get<double>(), 2.0);
}

TEST(TelemetrySummary, FromAFolderNothingIsFetchedPerByteNeeded) {
    TelemetrySummary summary;
    FrameTelemetry frame;
    frame.frameMs = 16.0;
    frame.timeS = 1.0;
    frame.storedBytesRead = 4096;
    summary.add(frame);
    const json j = summary.toJson();
    EXPECT_EQ(j["totals"]["stored_bytes_read"], 4096);
    EXPECT_TRUE(j["http"]["fetched_per_needed_byte"].is_null());
}

TEST(TelemetrySummary, SumsCountsKeepsPeaksAndTheLastCumulativeFaults) {
    TelemetrySummary summary;
    std::vector<double> frameMs;
    double timeS = 2.0;  // the run's clock started before the first frame we summarise
    constexpr std::uint64_t kFrames = 100;
    for (std::uint64_t i = 0; i < kFrames; ++i) {
        FrameTelemetry frame;
        frame.frame = i;
        frame.frameMs = 10.0 + static_cast<double>(i % 7);  // 10 ... 16 ms
        timeS += frame.frameMs / 1000.0;
        frame.timeS = timeS;
        frame.requestsMade = 3;
        frame.requestsCancelled = i % 2;
        frame.requestsCompleted = 2;
        frame.requestsFailed = i == 50 ? 1 : 0;
        frame.queueDepth = i == 40 ? 99 : 5;
        frame.ioInFlight = 1;
        frame.cpuCacheHits = 3;
        frame.cpuCacheMisses = 1;
        frame.cpuCacheEvictions = 1;
        frame.cpuCacheBytes = 1000 + i;
        frame.gpuLayersUsed = i == 70 ? 512 : 100;
        frame.gpuEvictions = 2;
        frame.gpuUploads = 4;
        frame.gpuUploadBytes = 4096;
        frame.gpuUploadsDeferred = i % 3 == 0 ? 1 : 0;
        frame.diskReadBytes = 10;
        frame.faultsTotal = i / 10;  // cumulative: 9 at the end
        frameMs.push_back(frame.frameMs);
        summary.add(frame);
    }
    const double expectedDurationS = timeS - 2.0;  // start of the first frame to the end

    const json j = summary.toJson();
    EXPECT_EQ(summary.frameCount(), kFrames);
    EXPECT_EQ(j["frames"], kFrames);
    EXPECT_NEAR(j["duration_s"].get<double>(), expectedDurationS, 1e-12);
    EXPECT_NEAR(j["throughput_tiles_per_s"].get<double>(), 200.0 / expectedDurationS, 1e-9);

    const json& totals = j["totals"];
    EXPECT_EQ(totals["requests_made"], 300);
    EXPECT_EQ(totals["requests_cancelled"], 50);
    EXPECT_EQ(totals["requests_completed"], 200);
    EXPECT_EQ(totals["requests_failed"], 1);
    EXPECT_EQ(totals["cpu_cache_hits"], 300);
    EXPECT_EQ(totals["cpu_cache_misses"], 100);
    EXPECT_DOUBLE_EQ(totals["cpu_cache_hit_rate"].get<double>(), 0.75);
    EXPECT_EQ(totals["cpu_cache_evictions"], 100);
    EXPECT_EQ(totals["gpu_evictions"], 200);
    EXPECT_EQ(totals["gpu_uploads"], 400);
    EXPECT_EQ(totals["gpu_upload_bytes"], 409600);
    EXPECT_EQ(totals["gpu_uploads_deferred"], 34);
    EXPECT_EQ(totals["disk_read_bytes"], 1000);
    EXPECT_EQ(totals["faults"], 9);

    EXPECT_EQ(j["peaks"]["queue_depth"], 99);
    EXPECT_EQ(j["peaks"]["cpu_cache_bytes"], 1099);
    EXPECT_EQ(j["peaks"]["gpu_layers_used"], 512);

    for (const auto& [key, p] : kPercentiles) {
        const double exact = exactPercentile(frameMs, p);
        EXPECT_NEAR(j["frame_ms"][key].get<double>(), exact,
                    exact * LatencyHistogram::kRelativeError)
            << key;
    }
    EXPECT_EQ(j["frame_ms"]["max"], 16.0);
}

TEST(TelemetrySummary, LoadLatenciesCountEveryLoad) {
    TelemetrySummary summary;
    std::vector<double> latencies;
    for (int i = 1; i <= 1000; ++i) {
        const double ms = 0.5 * i;  // 0.5 ... 500 ms
        latencies.push_back(ms);
        summary.addLoadLatency(ms);
    }
    const json j = summary.toJson()["load_latency_ms"];
    EXPECT_EQ(j["count"], 1000);
    for (const auto& [key, p] : kPercentiles) {
        const double exact = exactPercentile(latencies, p);
        EXPECT_NEAR(j[key].get<double>(), exact, exact * LatencyHistogram::kRelativeError) << key;
    }
    EXPECT_EQ(j["max"], 500.0);
    EXPECT_DOUBLE_EQ(j["mean"].get<double>(), 250.25);
    EXPECT_EQ(summary.loadLatencyMs().count(), 1000u);
}

TEST(TelemetrySummary, MergedLoadLatenciesCountLikeAddedOnes) {
    LatencyHistogram elsewhere;  // e.g. the streamer's histogram of every load
    TelemetrySummary added;
    for (double ms : {3.0, 30.0, 300.0}) {
        elsewhere.add(ms);
        added.addLoadLatency(ms);
    }
    TelemetrySummary merged;
    merged.addLoadLatency(1.0);
    merged.mergeLoadLatencies(elsewhere);
    added.addLoadLatency(1.0);
    EXPECT_EQ(merged.toJson()["load_latency_ms"], added.toJson()["load_latency_ms"]);
    EXPECT_EQ(merged.toJson()["load_latency_ms"]["count"], 4);
}

TEST(TelemetrySummary, OneFrameLastsItsFrameTimeAndNaNFrameTimesAreSkipped) {
    TelemetrySummary summary;
    FrameTelemetry frame;
    frame.timeS = 1.0;
    frame.frameMs = 250.0;
    frame.requestsCompleted = 5;
    summary.add(frame);
    EXPECT_DOUBLE_EQ(summary.durationS(), 0.25);
    EXPECT_DOUBLE_EQ(summary.toJson()["throughput_tiles_per_s"].get<double>(), 20.0);

    // A frame without a measured frame time still counts, but not in frame_ms.
    frame.timeS = 1.5;
    frame.frameMs = std::numeric_limits<double>::quiet_NaN();
    summary.add(frame);
    EXPECT_EQ(summary.frameCount(), 2u);
    EXPECT_EQ(summary.frameMs().count(), 1u);
    EXPECT_DOUBLE_EQ(summary.durationS(), 0.75);
    EXPECT_EQ(summary.toJson()["frame_ms"]["max"], 250.0);
    EXPECT_EQ(summary.toJson()["totals"]["requests_completed"], 10);
}

}  // namespace
}  // namespace terrain::runtime
