// parallelFor: runs body(i) for i in [0, count) on up to `threads` threads (the calling
// thread included) and returns when all are done. Indices are handed out one by one, so
// uneven work (a flat patch next to a rough one) still balances.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace terrain::io {

template <typename Body>
void parallelFor(std::int64_t count, unsigned threads, const Body& body) {
    std::atomic<std::int64_t> next{0};
    auto work = [&] {
        for (std::int64_t i = next++; i < count; i = next++) body(i);
    };
    const auto helpers = static_cast<std::int64_t>(std::max(1u, threads)) - 1;
    std::vector<std::jthread> pool;
    pool.reserve(static_cast<std::size_t>(std::min(helpers, count)));
    for (std::int64_t t = 0; t < std::min(helpers, count); ++t) pool.emplace_back(work);
    work();
}

}  // namespace terrain::io
