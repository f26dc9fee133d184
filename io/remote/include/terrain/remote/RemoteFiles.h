// RemoteFiles: the local copy of a file at an http(s):// URL, for readers that open files by
// path (a pyramid's manifest, shards and imagery tiles: issue 49). A file is fetched once into
// the disk cache (DiskCache.h: bounded in bytes, least recently used first out, kept across
// runs, shared by processes) and checked against the server once in a RemoteFiles' life with
// a conditional GET (If-None-Match / If-Modified-Since): unchanged costs a 304 and no body, a
// rebuilt file is fetched again. Transfers go through one libcurl handle (HttpClient.h:
// keep-alive, HTTP/2 where offered, timeouts, retries with backoff and jitter).
//
// Configured like GDAL's /vsicurl/, by environment, so a URL works wherever a pyramid path
// does without a flag in every tool:
//   TERRAIN_CACHE_DIR     the cache folder (default $XDG_CACHE_HOME/terrain, else
//                         ~/.cache/terrain)
//   TERRAIN_CACHE_BYTES   its bound in bytes (default 4 GiB; suffixes K, M, G)
//   TERRAIN_HTTP_TIMEOUT  seconds a request may take before it is retried (default 30)
//   TERRAIN_HTTP_RETRIES  attempts after the first (default 4)
//   TERRAIN_HTTP_MAX_PER_HOST  requests under way to one host at once, process-wide (default 6)
// One thread at a time (the I/O thread owns the reader's); readers on other threads make
// their own.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/remote/RemoteStats.h"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_set>

namespace terrain::remote {

/// True for a location that names a file or folder on a web server ("http://…", "https://…").
bool isRemoteLocation(std::string_view location);

struct CacheOptions {
    std::filesystem::path folder;
    std::uint64_t maxBytes = std::uint64_t{4} << 30;
    /// TERRAIN_CACHE_DIR and TERRAIN_CACHE_BYTES, with the defaults above; an unreadable
    /// TERRAIN_CACHE_BYTES is an Error naming it.
    static Result<CacheOptions> fromEnvironment();
};

struct HttpOptions {
    std::chrono::milliseconds connectTimeout{10'000};
    /// A request's whole time; a stalled body (under 1 KiB/s for 10 s) ends sooner.
    std::chrono::milliseconds requestTimeout{30'000};
    int retries = 4;  ///< attempts after the first, for failures worth retrying
    std::chrono::milliseconds firstBackoff{200};  ///< doubled each retry, times 0.5–1.5
    /// The most requests this process has under way to one host (scheme, host and port) at
    /// once, whatever its readers: the others wait their turn (HostSlots).
    int maxPerHost = 6;
    /// TERRAIN_HTTP_TIMEOUT, TERRAIN_HTTP_RETRIES and TERRAIN_HTTP_MAX_PER_HOST, with the
    /// defaults above.
    static Result<HttpOptions> fromEnvironment();
};

class DiskCache;
class HttpClient;

class RemoteFiles {
public:
    static Result<std::unique_ptr<RemoteFiles>> open(const CacheOptions& cache,
                                                     const HttpOptions& http);
    /// open() with both from the environment.
    static Result<std::unique_ptr<RemoteFiles>> fromEnvironment();
    ~RemoteFiles();
    RemoteFiles(const RemoteFiles&) = delete;
    RemoteFiles& operator=(const RemoteFiles&) = delete;

    /// The path of a complete local copy of `url`: from the cache (checked with the server the
    /// first time this object is asked for it) or fetched now. A server that cannot be reached
    /// after the retries leaves a cached copy usable (counted in staleServed). Errors name
    /// the URL and what the server or the network said ("HTTP 404", "cannot connect: …").
    Result<std::filesystem::path> localCopy(const std::string& url);

    const RemoteStats& stats() const { return m_stats; }

private:
    RemoteFiles(std::unique_ptr<DiskCache> cache, std::unique_ptr<HttpClient> http);

    std::unique_ptr<DiskCache> m_cache;
    std::unique_ptr<HttpClient> m_http;
    std::unordered_set<std::string> m_checked;  // URLs confirmed with the server by this object
    RemoteStats m_stats;
};

/// The RemoteFiles a reader of `location` fetches through: one from the environment
/// (RemoteFiles::fromEnvironment) for a URL, null for a local path.
Result<std::unique_ptr<RemoteFiles>> filesFor(std::string_view location);

/// `folder` + "/" + `name` for a URL folder (no path normalisation: "//" after the scheme
/// stays).
std::string joinUrl(std::string_view folder, std::string_view name);

}  // namespace terrain::remote
