// RemoteStats: what a RemoteFiles (RemoteFiles.h) did over HTTP, counted for telemetry and
// tests. Apart from RemoteFiles so that a reader's public header can hand its counts out
// without the HTTP client's declarations (PyramidReader::remoteStats, IoThreadStats::http).
#pragma once

#include <cstdint>

namespace terrain::remote {

/// What a RemoteFiles did, for telemetry and tests.
struct RemoteStats {
    std::uint64_t requests = 0;      ///< HTTP requests sent, retries included
    std::uint64_t retries = 0;       ///< of them, repeats after a failure
    std::uint64_t fetched = 0;       ///< bodies that came: files (200) and ranges (206)
    std::uint64_t fetchedBytes = 0;  ///< their bytes
    std::uint64_t notModified = 0;   ///< cached files the server confirmed (304)
    std::uint64_t cacheHits = 0;     ///< local copies used without a request
    std::uint64_t staleServed = 0;   ///< cached copies used because the server could not be had

    RemoteStats& operator+=(const RemoteStats& more) {
        requests += more.requests;
        retries += more.retries;
        fetched += more.fetched;
        fetchedBytes += more.fetchedBytes;
        notModified += more.notModified;
        cacheHits += more.cacheHits;
        staleServed += more.staleServed;
        return *this;
    }
    /// What happened between an earlier snapshot `before` of the same counters and this one.
    RemoteStats since(const RemoteStats& before) const {
        return {requests - before.requests,       retries - before.retries,
                fetched - before.fetched,         fetchedBytes - before.fetchedBytes,
                notModified - before.notModified, cacheHits - before.cacheHits,
                staleServed - before.staleServed};
    }
};

}  // namespace terrain::remote
