// terrain-test-proxy: tests/support/FaultProxy.h as a program, for benchmarks that need a
// slow or lossy network in front of a real server (tools/bench/remote_arrival_bench.py):
//   terrain-test-proxy UPSTREAM_PORT [LATENCY_MS] [DROP_EVERY] [LOSS_PERCENT] [WINDOW] [LINK_MBPS]
// forwards 127.0.0.1:<a free port> to 127.0.0.1:UPSTREAM_PORT, waiting LATENCY_MS before
// every answer (a round trip's delay), closing every DROP_EVERY-th request's connection
// unanswered (0, the default: none) and losing LOSS_PERCENT of the packets (requests and
// answers' segments; each loss stalls its stream a round trip, or 200 ms near a transfer's
// end: FaultPlan::segmentLoss; 0, the default: none), sending answers a congestion window at
// a time from WINDOW segments (FaultPlan::initialWindow; 0, the default: at once), through one
// link of LINK_MBPS megabits a second that every connection shares
// (FaultPlan::linkBytesPerSecond; 0, the default: no cap). Prints
// "port N" on stdout once it
// listens, and runs until its standard input closes. Not installed: a test helper.
#include "FaultProxy.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
    if (argc < 2 || argc > 7) {
        std::fprintf(stderr,
                     "usage: %s UPSTREAM_PORT [LATENCY_MS] [DROP_EVERY] [LOSS_PERCENT] [WINDOW] "
                     "[LINK_MBPS]\n",
                     argv[0]);
        return 2;
    }
    const int upstream = std::atoi(argv[1]);
    const int latencyMs = argc > 2 ? std::atoi(argv[2]) : 0;
    const int dropEvery = argc > 3 ? std::atoi(argv[3]) : 0;
    const double lossPercent = argc > 4 ? std::atof(argv[4]) : 0.0;
    const int window = argc > 5 ? std::atoi(argv[5]) : 0;
    const double linkMbps = argc > 6 ? std::atof(argv[6]) : 0.0;
    if (upstream <= 0 || upstream > 65535 || latencyMs < 0 || dropEvery < 0 || window < 0 ||
        !(lossPercent >= 0.0 && lossPercent <= 100.0) || !(linkMbps >= 0.0 && linkMbps < 1e6)) {
        std::fprintf(stderr, "%s: bad arguments\n", argv[0]);
        return 2;
    }
    terrain::test::FaultProxy proxy(
        upstream, terrain::test::FaultPlan{.latency = std::chrono::milliseconds(latencyMs),
                                           .faultEvery = dropEvery,
                                           .oncePerPath = false,
                                           .kinds = {terrain::test::ProxyFault::Drop},
                                           .segmentLoss = lossPercent / 100.0,
                                           .initialWindow = static_cast<std::size_t>(window),
                                           .linkBytesPerSecond = linkMbps * 1e6 / 8.0});
    if (!proxy.ready()) {
        std::fprintf(stderr, "%s: cannot listen on 127.0.0.1\n", argv[0]);
        return 1;
    }
    const std::string url = proxy.url("");
    std::printf("port %s\n",
                url.substr(url.rfind(':') + 1, url.size() - url.rfind(':') - 2).c_str());
    std::fflush(stdout);
    while (std::getchar() != EOF) {
    }
    return 0;
}
