// RemoteFiles: the local copy of a file at an http(s):// URL, for readers that open files by
// path (a pyramid's manifest, shards and imagery tiles: issue 49). A file is fetched once into
// the disk cache (DiskCache.h: bounded in bytes, least recently used first out, kept across
// runs, shared by processes) and checked against the server once in a RemoteFiles' life with
// a conditional GET (If-None-Match / If-Modified-Since): unchanged costs a 304 and no body, a
// rebuilt file is fetched again. Large files a reader wants parts of (shards) are read by
// ranges instead (RemoteFile). Transfers go through one libcurl handle (HttpClient.h:
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
//   TERRAIN_HTTP_RANGE_BYTES   bytes a range request of a shard asks for at least (default 64K;
//                              0: shards come whole)
// One thread at a time (the I/O thread owns the reader's); readers on other threads make
// their own, sharing what this run has confirmed and is fetching (RemoteRun).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/remote/RemoteStats.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

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
    /// A file read by ranges (RemoteFile, a pyramid's shards): its first request asks for this
    /// many bytes, and a read of bytes not yet here fetches them with what follows up to this
    /// many; a file of at most 4 × this comes whole with its second request. A multiple of
    /// 16 KiB; 0: such files come whole, as other files do.
    std::uint64_t rangeBytes = 64 * 1024;
    std::uint64_t wholeFileBytes() const { return 4 * rangeBytes; }
    /// TERRAIN_HTTP_TIMEOUT, TERRAIN_HTTP_RETRIES, TERRAIN_HTTP_MAX_PER_HOST and
    /// TERRAIN_HTTP_RANGE_BYTES, with the defaults above.
    static Result<HttpOptions> fromEnvironment();
};

/// What one run's readers of remote files share (the RemoteFiles of an IoThread's reader
/// threads, one each): the URLs confirmed with the server, so that a file is confirmed once a
/// run, not once a reader; and the blocks of files read by ranges that a reader is fetching,
/// so that two readers wanting the same bytes at once fetch them once (a whole file is
/// fetched once through the cache entry's lock; a range fetch does not hold it). Thread-safe.
class RemoteRun {
public:
    bool confirmed(const std::string& url) const;
    void confirm(const std::string& url);

    /// Blocks [from, end] of `url` (end ≤ to) claimed for the caller to fetch: up to the first
    /// block another reader is fetching. When block `from` itself is being fetched, waits until
    /// that fetch is over and returns nullopt: look again at what the cache holds.
    std::optional<std::pair<std::size_t, std::size_t>> claim(const std::string& url,
                                                             std::size_t from, std::size_t to);
    /// Ends a claim (the blocks fetched and recorded, or the fetch failed).
    void release(const std::string& url, std::size_t from, std::size_t end);

private:
    mutable std::mutex m_mutex;
    std::condition_variable m_released;
    std::unordered_set<std::string> m_urls;
    // Per URL, the claimed block ranges [from, end].
    std::unordered_map<std::string, std::vector<std::pair<std::size_t, std::size_t>>> m_claims;
};

class DiskCache;
class HttpClient;
class RemoteFiles;
struct PartialFile;

/// A file at a URL read by ranges (RemoteFiles::openRanged): only the blocks a read needs are
/// fetched (HTTP range requests, RFC 9110 §14), into a partial entry of the disk cache that
/// later reads, runs and processes use. For large files of which a reader wants a few parts,
/// as a pyramid's shard files: a patch costs its own bytes, not its shard's.
class RemoteFile {
public:
    ~RemoteFile();
    RemoteFile(const RemoteFile&) = delete;
    RemoteFile& operator=(const RemoteFile&) = delete;

    const std::string& url() const { return m_url; }
    std::uint64_t size() const;

    /// Bytes [offset, offset + out.size()) of the file, fetching the blocks the cache does
    /// not hold (with If-Range, so the bytes all come from the version first seen). An Error
    /// names the URL: beyond the file's end, the network, or the file changed on the server
    /// while it was being read.
    Status read(std::uint64_t offset, std::span<char> out);

private:
    friend class RemoteFiles;
    RemoteFile(RemoteFiles& files, std::string url, std::unique_ptr<PartialFile> entry, int fd);
    // Fetches missing blocks from the first missing one in [firstBlock, lastBlock]: true when
    // it did, false when it waited for another reader of the run fetching that block.
    Result<bool> fetch(std::size_t firstBlock, std::size_t lastBlock);

    // The most a fetch grows to: 2 MiB of blocks.
    static constexpr std::size_t kMaxFetchBlocks = 128;

    RemoteFiles& m_files;
    std::string m_url;
    std::unique_ptr<PartialFile> m_entry;  // the blocks this object knows to be in the data file
    int m_fd = -1;                         // the data file, read and written by position
    std::size_t m_fetchBlocks = 0;         // the last fetch's worth, in blocks (0: none yet)
    std::size_t m_fetchEnd = 0;            // the block after the last fetch's last
};

class RemoteFiles {
public:
    /// `run`: shared with other readers of this run (null: this object's own).
    static Result<std::unique_ptr<RemoteFiles>> open(const CacheOptions& cache,
                                                     const HttpOptions& http,
                                                     std::shared_ptr<RemoteRun> run = nullptr);
    /// open() with both from the environment.
    static Result<std::unique_ptr<RemoteFiles>> fromEnvironment(
        std::shared_ptr<RemoteRun> run = nullptr);
    ~RemoteFiles();
    RemoteFiles(const RemoteFiles&) = delete;
    RemoteFiles& operator=(const RemoteFiles&) = delete;

    /// The path of a complete local copy of `url`: from the cache (checked with the server the
    /// first time this object is asked for it) or fetched now. A server that cannot be reached
    /// after the retries leaves a cached copy usable (counted in staleServed). Errors name
    /// the URL and what the server or the network said ("HTTP 404", "cannot connect: …").
    Result<std::filesystem::path> localCopy(const std::string& url);

    /// `url` to be read by ranges (RemoteFile): checked with the server the first time this
    /// run is asked for it, with a conditional request for its first HttpOptions::rangeBytes,
    /// which a new entry keeps (the headers and tables a reader wants first). A file of at
    /// most HttpOptions::wholeFileBytes() comes whole at once (every file does with a
    /// rangeBytes of 0). Errors as localCopy's.
    Result<std::unique_ptr<RemoteFile>> openRanged(const std::string& url);

    const RemoteStats& stats() const { return m_stats; }

private:
    friend class RemoteFile;
    // Counts `outcome` (a hit, a 304, a stale copy), takes `url` as confirmed this run and
    // marks its entry used now.
    void used(const std::string& url, std::uint64_t& outcome);
    static Error notModifiedWithoutCopy(const std::string& url);
    // Keeps a body that is the whole file as a complete entry and opens it.
    Result<std::unique_ptr<RemoteFile>> keepWhole(const std::string& url, const std::string& body,
                                                  const std::string& etag,
                                                  const std::string& lastModified);
    Result<std::unique_ptr<RemoteFile>> openEntry(const std::string& url, PartialFile entry);

    RemoteFiles(std::unique_ptr<DiskCache> cache, std::unique_ptr<HttpClient> http,
                std::shared_ptr<RemoteRun> run);

    std::unique_ptr<DiskCache> m_cache;
    std::unique_ptr<HttpClient> m_http;
    std::shared_ptr<RemoteRun> m_run;  // URLs confirmed with the server, ranges being fetched
    RemoteStats m_stats;
};

/// The RemoteFiles a reader of `location` fetches through: one from the environment
/// (RemoteFiles::fromEnvironment, with `run`) for a URL, null for a local path.
Result<std::unique_ptr<RemoteFiles>> filesFor(std::string_view location,
                                              std::shared_ptr<RemoteRun> run = nullptr);

/// `folder` + "/" + `name` for a URL folder (no path normalisation: "//" after the scheme
/// stays).
std::string joinUrl(std::string_view folder, std::string_view name);

}  // namespace terrain::remote
