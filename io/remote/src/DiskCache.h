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
// A meta file's modification time is the entry's last use.
//
// A file read by ranges (RemoteFile) is a partial entry: its data file has the file's whole
// size, with holes where blocks of kCacheBlockBytes have not come, and its meta file also
// records the size and which blocks are there ("blocks", hex). Blocks are written into the
// data file, then recorded, under the entry's lock; a block once recorded is never rewritten,
// so a reader that saw it recorded may read it without a lock. When every block has come the
// entry becomes a complete one (no "blocks"), which find() returns. Trimming (after each store)
// holds an exclusive flock on <folder>/lock, removes the least recently used entries until the
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
#include <vector>

namespace terrain::remote {

struct CachedFile {
    std::filesystem::path data;
    std::string etag;
    std::string lastModified;
    std::uint64_t bytes = 0;
    /// When the entry was last stored, confirmed or used (its meta file's time).
    std::filesystem::file_time_type used{};
};

/// A partial entry's blocks are this many bytes (the last one maybe shorter).
inline constexpr std::uint64_t kCacheBlockBytes = 16 * 1024;

/// An entry as a range reader sees it: complete (every block there) or partial.
struct PartialFile {
    std::filesystem::path data;
    std::string etag;
    std::string lastModified;
    std::uint64_t size = 0;    ///< the whole file's bytes
    std::vector<bool> blocks;  ///< which blocks of kCacheBlockBytes the data file holds
    std::filesystem::file_time_type used{};

};

/// The blocks a file of `size` bytes has.
std::size_t blocksOfFile(std::uint64_t size);

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

    /// `url`'s entry, complete or partial (a complete one has every block), or nullopt.
    std::optional<PartialFile> findPartial(const std::string& url) const;

    /// Makes a new partial entry of `url` with no block yet: a data file of `size` bytes
    /// (holes) and its meta file, replacing an older entry. Call with the entry's lock held.
    Result<PartialFile> startPartial(const std::string& url, const std::string& etag,
                                     const std::string& lastModified, std::uint64_t size);

    /// Records that `file`'s data file now holds `file.blocks` too (written there by the
    /// caller). Call with the entry's lock held. Returns the blocks the entry holds now (its
    /// recorded ones and these), or nullopt when the entry is no longer that data file
    /// (trimmed, or replaced by another version): the caller's blocks then stay its own.
    std::optional<std::vector<bool>> recordBlocks(const std::string& url, const PartialFile& file);

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
    // Bytes recorded by recordBlocks since this object last trimmed: a range is small, so the
    // cache is trimmed once enough of them have come rather than after each.
    std::uint64_t m_recordedSinceTrim = 0;
};

}  // namespace terrain::remote
