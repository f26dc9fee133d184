// DiskCache: fetched files kept on disk across runs, bounded in bytes, the least recently used
// removed first, safe with several processes on one folder.
//
// Layout: <folder>/v1/<host>/<path of the URL>, each segment percent-encoded to [A-Za-z0-9._~-].
// An entry is two files: "<name>.meta" (JSON: the URL, its ETag and Last-Modified, the body's
// bytes, and the name of its data file) and the data file "<name>.<16 hex digits>", written
// under a temporary name and renamed into place before the meta file is (atomically)
// replaced. So a reader that finds a meta file finds a complete data file of the size it
// records, or none (a truncated or removed one is a miss); a data file is never rewritten,
// only replaced by a new name, so a process that has one open keeps reading what it opened.
// A meta file's modification time is the entry's last use. Trimming (after each store) holds
// an exclusive flock on <folder>/lock, removes the least recently used entries until the
// bytes fit, and temporary or unreferenced data files over ten minutes old (what a process
// killed while writing leaves).
#pragma once

#include "terrain/base/AtomicFile.h"
#include "terrain/base/Result.h"
#include "terrain/remote/RemoteFiles.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace terrain::remote {

struct CachedFile {
    std::filesystem::path data;
    std::string etag;
    std::string lastModified;
    std::uint64_t bytes = 0;
    /// When the entry was last stored, confirmed or used (its meta file's time).
    std::filesystem::file_time_type used{};
};

/// An exclusive flock on one entry's "<name>.lock" for as long as it lives (DiskCache::
/// lockEntry): held while the entry is fetched or confirmed, so that of the threads and
/// processes that want one URL at once, one asks the server and the others use its answer.
class EntryLock {
public:
    explicit EntryLock(int fd) : m_fd(fd) {}
    EntryLock(EntryLock&& other) noexcept : m_fd(std::exchange(other.m_fd, -1)) {}
    EntryLock& operator=(EntryLock&&) = delete;
    EntryLock(const EntryLock&) = delete;
    ~EntryLock();

private:
    int m_fd = -1;
};

class DiskCache {
public:
    /// Creates the folder if needed; an Error names it when it cannot be made or written.
    static Result<std::unique_ptr<DiskCache>> open(const CacheOptions& options);

    /// The complete entry of `url`, or nullopt.
    std::optional<CachedFile> find(const std::string& url) const;

    /// A temporary file beside where `url`'s entry goes, for the body to be written into.
    Result<AtomicFile> reserve(const std::string& url) const;

    /// Makes the written `body` (reserve()'s, closed) the entry of `url` with its validators,
    /// replacing an older entry, then trims the cache (keeping this entry).
    Result<CachedFile> store(const std::string& url, AtomicFile body, const std::string& etag,
                             const std::string& lastModified, std::uint64_t bytes);

    /// Waits for, then takes, the lock of `url`'s entry.
    Result<EntryLock> lockEntry(const std::string& url) const;

    /// Marks the entry used now (least recently used goes first).
    void touch(const std::string& url) const;

    /// Removes least recently used entries (never `keep`'s) until the cache holds at most
    /// maxBytes, and stale temporary and unreferenced files. Returns the bytes held (more than
    /// maxBytes only when `keep` alone is).
    Result<std::uint64_t> trim(const std::string& keep = {}) const;

    const std::filesystem::path& folder() const { return m_options.folder; }

private:
    explicit DiskCache(const CacheOptions& options) : m_options(options) {}
    std::filesystem::path metaPathOf(const std::string& url) const;

    CacheOptions m_options;
};

}  // namespace terrain::remote
