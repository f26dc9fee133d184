// terrain-test-proxy: tests/support/FaultProxy.h as a program, for benchmarks that need a
// slow or lossy network in front of a real server (tools/bench/remote_arrival_bench.py):
//   terrain-test-proxy UPSTREAM_PORT [LATENCY_MS] [DROP_EVERY]
// forwards 127.0.0.1:<a free port> to 127.0.0.1:UPSTREAM_PORT, waiting LATENCY_MS before
// every answer (a round trip's delay) and closing every DROP_EVERY-th request's connection
// unanswered (0, the default: none). Prints "port N" on stdout once it
// listens, and runs until its standard input closes. Not installed: a test helper.
#include "FaultProxy.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
    if (argc < 2 || argc > 4) {
        std::fprintf(stderr, "usage: %s UPSTREAM_PORT [LATENCY_MS] [DROP_EVERY]\n", argv[0]);
        return 2;
    }
    const int upstream = std::atoi(argv[1]);
    const int latencyMs = argc > 2 ? std::atoi(argv[2]) : 0;
    const int dropEvery = argc > 3 ? std::atoi(argv[3]) : 0;
    if (upstream <= 0 || upstream > 65535 || latencyMs < 0 || dropEvery < 0) {
        std::fprintf(stderr, "%s: bad arguments\n", argv[0]);
        return 2;
    }
    terrain::test::FaultProxy proxy(
        upstream, terrain::test::FaultPlan{.latency = std::chrono::milliseconds(latencyMs),
                                           .faultEvery = dropEvery,
                                           .oncePerPath = false,
                                           .kinds = {terrain::test::ProxyFault::Drop}});
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
