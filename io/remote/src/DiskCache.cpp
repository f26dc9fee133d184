#include "DiskCache.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <unordered_set>
#include <vector>

namespace terrain::remote {
namespace fs = std::filesystem;
namespace {

constexpr std::string_view kLayoutVersion = "v1";
constexpr std::string_view kMetaExtension = ".meta";
constexpr std::string_view kLockExtension = ".lock";
constexpr auto kStaleAfter = std::chrono::minutes(10);

// One segment of a URL as a file name: [A-Za-z0-9._~-] kept, every other byte %XX, and the
// names "." and ".." (and an empty one) encoded whole so no segment leaves its folder.
std::string segmentName(std::string_view segment) {
    if (segment.empty()) return "%";
    if (segment == "." || segment == "..") {
        std::string out;
        for (std::size_t i = 0; i < segment.size(); ++i) out += "%2E";
        return out;
    }
    std::string out;
    for (const char c : segment) {
        const auto u = static_cast<unsigned char>(c);
        if (std::isalnum(u) || c == '.' || c == '_' || c == '~' || c == '-')
            out += c;
        else
            out += fmt::format("%{:02X}", u);
    }
    return out;
}

// "<scheme>://<host>/<a>/<b>?q" → v1/<scheme>%3A<host>/<a>/<b>%3Fq (the scheme kept apart
// so http and https copies of one host never mix).
fs::path relativePathOf(const std::string& url) {
    const std::size_t schemeEnd = url.find("://");
    const std::string_view scheme = std::string_view(url).substr(0, schemeEnd);
    std::string_view rest = std::string_view(url).substr(schemeEnd + 3);
    const std::size_t slash = rest.find('/');
    const std::string_view host = rest.substr(0, slash);
    fs::path path = fs::path(kLayoutVersion) / segmentName(fmt::format("{}:{}", scheme, host));
    if (slash == std::string_view::npos) return path / "%";
    rest.remove_prefix(slash + 1);
    while (true) {
        const std::size_t next = rest.find('/');
        path /= segmentName(rest.substr(0, next));
        if (next == std::string_view::npos) break;
        rest.remove_prefix(next + 1);
    }
    return path;
}

struct Meta {
    std::string url;
    std::string etag;
    std::string lastModified;
    std::uint64_t bytes = 0;
    std::string data;  // the data file's name, in the meta file's folder
    // A partial entry's: the whole file's size and the blocks the data file holds (empty for
    // a complete entry, whose size is `bytes`).
    std::uint64_t size = 0;
    std::vector<bool> blocks;
};

// Blocks as hex digits, four blocks a digit, block 4k + b in bit b of digit k.
std::string blocksText(const std::vector<bool>& blocks) {
    std::string text((blocks.size() + 3) / 4, '0');
    for (std::size_t i = 0; i < blocks.size(); ++i)
        if (blocks[i]) {
            char& digit = text[i / 4];
            const int value = (digit <= '9' ? digit - '0' : digit - 'a' + 10) | (1 << (i % 4));
            digit = static_cast<char>(value < 10 ? '0' + value : 'a' + value - 10);
        }
    return text;
}

std::optional<std::vector<bool>> blocksFromText(const std::string& text, std::size_t count) {
    if (text.size() != (count + 3) / 4) return std::nullopt;
    std::vector<bool> blocks(count, false);
    for (std::size_t i = 0; i < count; ++i) {
        const char digit = text[i / 4];
        int value = 0;
        if (digit >= '0' && digit <= '9')
            value = digit - '0';
        else if (digit >= 'a' && digit <= 'f')
            value = digit - 'a' + 10;
        else
            return std::nullopt;
        blocks[i] = (value >> (i % 4) & 1) != 0;
    }
    return blocks;
}

std::uint64_t bytesOfBlocks(const std::vector<bool>& blocks, std::uint64_t size) {
    std::uint64_t bytes = 0;
    for (std::size_t i = 0; i < blocks.size(); ++i)
        if (blocks[i])
            bytes += std::min<std::uint64_t>(kCacheBlockBytes, size - i * kCacheBlockBytes);
    return bytes;
}

std::string metaText(const Meta& m) {
    nlohmann::json j = {{"url", m.url},
                        {"etag", m.etag},
                        {"lastModified", m.lastModified},
                        {"bytes", m.bytes},
                        {"data", m.data}};
    if (!m.blocks.empty()) {
        j["size"] = m.size;
        j["blocks"] = blocksText(m.blocks);
    }
    return j.dump();
}

std::optional<Meta> readMeta(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream text;
    text << in.rdbuf();
    try {
        const nlohmann::json j = nlohmann::json::parse(text.str());
        Meta m;
        m.url = j.at("url").get<std::string>();
        m.etag = j.value("etag", "");
        m.lastModified = j.value("lastModified", "");
        m.bytes = j.at("bytes").get<std::uint64_t>();
        m.data = j.at("data").get<std::string>();
        m.size = m.bytes;
        if (j.contains("blocks")) {
            m.size = j.at("size").get<std::uint64_t>();
            std::optional<std::vector<bool>> blocks =
                blocksFromText(j.at("blocks").get<std::string>(), blocksOfFile(m.size));
            if (!blocks || bytesOfBlocks(*blocks, m.size) != m.bytes) return std::nullopt;
            m.blocks = std::move(*blocks);
        }
        // A data name that could leave the folder is no entry of ours.
        if (m.data.empty() || m.data.find('/') != std::string::npos || m.data.starts_with("."))
            return std::nullopt;
        return m;
    } catch (const nlohmann::json::exception&) {
        return std::nullopt;  // damaged: a miss, replaced by the next store
    }
}

// An exclusive flock on <folder>/lock for as long as it lives.
class CacheLock {
public:
    explicit CacheLock(const fs::path& folder) {
        m_fd = ::open((folder / "lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (m_fd >= 0)
            while (::flock(m_fd, LOCK_EX) != 0 && errno == EINTR) {
            }
    }
    ~CacheLock() {
        if (m_fd >= 0) ::close(m_fd);  // closing releases the lock
    }
    CacheLock(const CacheLock&) = delete;
    CacheLock& operator=(const CacheLock&) = delete;
    bool held() const { return m_fd >= 0; }

private:
    int m_fd = -1;
};

}  // namespace

std::size_t blocksOfFile(std::uint64_t size) {
    return static_cast<std::size_t>((size + kCacheBlockBytes - 1) / kCacheBlockBytes);
}

Result<std::unique_ptr<DiskCache>> DiskCache::open(const CacheOptions& options) {
    std::error_code ec;
    fs::create_directories(options.folder / kLayoutVersion, ec);
    if (ec)
        return Error{fmt::format("{}: cannot make the remote pyramid cache there: {}",
                                 options.folder.string(), ec.message())};
    if (::access(options.folder.c_str(), W_OK) != 0)
        return Error{fmt::format("{}: the remote pyramid cache folder is not writable: {}",
                                 options.folder.string(), std::strerror(errno))};
    return std::unique_ptr<DiskCache>(new DiskCache(options));
}

fs::path DiskCache::metaPathOf(const std::string& url) const {
    fs::path path = m_options.folder / relativePathOf(url);
    path += std::string(kMetaExtension);
    return path;
}

std::optional<CachedFile> DiskCache::find(const std::string& url) const {
    const fs::path metaPath = metaPathOf(url);
    const std::optional<Meta> meta = readMeta(metaPath);
    // A partial entry is no copy of the file.
    if (!meta || meta->url != url || !meta->blocks.empty()) return std::nullopt;
    const fs::path data = metaPath.parent_path() / meta->data;
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(data, ec);
    if (ec || size != meta->bytes) return std::nullopt;  // removed or truncated: a miss
    const fs::file_time_type used = fs::last_write_time(metaPath, ec);
    return CachedFile{data, meta->etag, meta->lastModified, meta->bytes, used};
}

std::optional<PartialFile> DiskCache::findPartial(const std::string& url) const {
    const fs::path metaPath = metaPathOf(url);
    const std::optional<Meta> meta = readMeta(metaPath);
    if (!meta || meta->url != url) return std::nullopt;
    const fs::path data = metaPath.parent_path() / meta->data;
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(data, ec);
    if (ec || size != meta->size) return std::nullopt;  // removed or truncated: a miss
    PartialFile file{data,       meta->etag,   meta->lastModified,
                     meta->size, meta->blocks, fs::last_write_time(metaPath, ec)};
    if (file.blocks.empty()) file.blocks.assign(blocksOfFile(file.size), true);
    return file;
}

Result<PartialFile> DiskCache::startPartial(const std::string& url, const std::string& etag,
                                            const std::string& lastModified, std::uint64_t size) {
    Result<AtomicFile> reserved = reserve(url);
    if (!reserved) return reserved.error();
    AtomicFile body = std::move(reserved).value();
    // Holes where the blocks will go: the file system keeps them unallocated.
    std::error_code ec;
    fs::resize_file(body.temporaryPath(), size, ec);
    if (ec)
        return Error{fmt::format("{}: cannot make its cache entry {}: {}", url,
                                 body.temporaryPath().string(), ec.message())};
    PartialFile file{body.path(),
                     etag,
                     lastModified,
                     size,
                     std::vector<bool>(blocksOfFile(size), false),
                     fs::file_time_type::clock::now()};
    const fs::path metaPath = metaPathOf(url);
    const std::optional<Meta> previous = readMeta(metaPath);
    if (Status committed = body.commit(); !committed)
        return Error{
            fmt::format("{}: cannot keep it in the cache: {}", url, committed.error().message)};
    Meta meta{url, etag, lastModified, 0, file.data.filename().string(), size, file.blocks};
    if (size == 0) meta.blocks.clear();  // nothing to come: complete already
    if (Status written = writeTextAtomically(metaPath, metaText(meta)); !written) {
        fs::remove(file.data, ec);
        return written.error();
    }
    if (previous && previous->data != meta.data)
        fs::remove(metaPath.parent_path() / previous->data, ec);  // an open reader keeps it
    return file;
}

std::optional<std::vector<bool>> DiskCache::recordBlocks(const std::string& url,
                                                         const PartialFile& file) {
    const fs::path metaPath = metaPathOf(url);
    std::optional<Meta> meta = readMeta(metaPath);
    if (!meta || meta->url != url || meta->data != file.data.filename().string() ||
        meta->size != file.size)
        return std::nullopt;
    std::vector<bool> blocks = std::move(meta->blocks);
    if (blocks.empty()) return std::vector<bool>(blocksOfFile(file.size), true);  // complete
    for (std::size_t i = 0; i < blocks.size() && i < file.blocks.size(); ++i)
        blocks[i] = blocks[i] || file.blocks[i];
    const std::uint64_t before = meta->bytes;
    meta->bytes = bytesOfBlocks(blocks, file.size);
    if (std::find(blocks.begin(), blocks.end(), false) == blocks.end())
        meta->blocks.clear();  // every block has come: a complete entry, which find() returns
    else
        meta->blocks = blocks;
    if (!writeTextAtomically(metaPath, metaText(*meta))) return std::nullopt;
    m_recordedSinceTrim += meta->bytes - before;
    // Trimming lists the whole cache: done once a sixteenth of the bound (at most 4 MiB) has
    // come in ranges, not after each range.
    if (m_recordedSinceTrim >= std::min<std::uint64_t>(m_options.maxBytes / 16, 4 << 20)) {
        m_recordedSinceTrim = 0;
        (void)trim(url);  // a failed trim leaves the cache over its bound until the next
    }
    return blocks;
}

EntryLock::~EntryLock() {
    if (m_fd >= 0) ::close(m_fd);  // closing releases the lock
}

Result<EntryLock> DiskCache::lockEntry(const std::string& url) const {
    fs::path lockPath = metaPathOf(url);
    lockPath.replace_extension(std::string(kLockExtension));
    std::error_code ec;
    fs::create_directories(lockPath.parent_path(), ec);
    const int fd = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
        return Error{fmt::format("{}: cannot lock its cache entry {}: {}", url, lockPath.string(),
                                 std::strerror(errno))};
    while (::flock(fd, LOCK_EX) != 0) {
        if (errno == EINTR) continue;
        const int error = errno;
        ::close(fd);
        return Error{fmt::format("{}: cannot lock its cache entry {}: {}", url, lockPath.string(),
                                 std::strerror(error))};
    }
    return EntryLock(fd);
}

Result<AtomicFile> DiskCache::reserve(const std::string& url) const {
    const fs::path metaPath = metaPathOf(url);
    std::error_code ec;
    fs::create_directories(metaPath.parent_path(), ec);
    if (ec)
        return Error{fmt::format("{}: cannot make {}: {}", url, metaPath.parent_path().string(),
                                 ec.message())};
    // A new data name each time: a data file is never rewritten in place.
    static thread_local std::mt19937_64 names(std::random_device{}());
    fs::path data = metaPath;
    data.replace_extension();  // drops ".meta"
    data += fmt::format(".{:016x}", names());
    return AtomicFile::create(data);
}

Result<CachedFile> DiskCache::store(const std::string& url, AtomicFile body,
                                    const std::string& etag, const std::string& lastModified,
                                    std::uint64_t bytes) {
    const fs::path metaPath = metaPathOf(url);
    const std::optional<Meta> previous = readMeta(metaPath);
    const fs::path data = body.path();
    if (Status committed = body.commit(); !committed)
        return Error{
            fmt::format("{}: cannot keep it in the cache: {}", url, committed.error().message)};
    const Meta meta{url, etag, lastModified, bytes, data.filename().string(), bytes, {}};
    Status written = writeTextAtomically(metaPath, metaText(meta));
    if (!written) {
        std::error_code ec;
        fs::remove(data, ec);
        return written.error();
    }
    if (previous && previous->data != data.filename().string()) {
        std::error_code ec;  // an open reader of it keeps reading it
        fs::remove(metaPath.parent_path() / previous->data, ec);
    }
    if (Result<std::uint64_t> trimmed = trim(url); !trimmed) return trimmed.error();
    return CachedFile{data, etag, lastModified, bytes, fs::file_time_type::clock::now()};
}

void DiskCache::touch(const std::string& url) const {
    std::error_code ec;  // a lost touch only makes the entry look older
    fs::last_write_time(metaPathOf(url), fs::file_time_type::clock::now(), ec);
}

Result<std::uint64_t> DiskCache::trim(const std::string& keep) const {
    CacheLock lock(m_options.folder);
    if (!lock.held())
        return Error{fmt::format("{}: cannot lock the remote pyramid cache: {}",
                                 m_options.folder.string(), std::strerror(errno))};
    struct Entry {
        fs::path meta;
        fs::path data;
        fs::file_time_type used;
        std::uint64_t bytes = 0;
    };
    std::vector<Entry> entries;
    std::vector<std::pair<fs::path, fs::file_time_type>> others;
    std::unordered_set<std::string> referenced;
    std::uint64_t held = 0;
    const fs::path keepMeta = keep.empty() ? fs::path{} : metaPathOf(keep);
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(m_options.folder / kLayoutVersion, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        const fs::path& path = it->path();
        const fs::file_time_type time = it->last_write_time(ec);
        // Temporary files (AtomicFile's ".<stem>.tmp-…") are never entries, whatever their
        // extension.
        const bool temporary = path.filename().string().starts_with(".");
        if (path.extension() == kMetaExtension && !temporary) {
            const std::optional<Meta> meta = readMeta(path);
            if (!meta) {
                others.emplace_back(path, time);
                continue;
            }
            const fs::path data = path.parent_path() / meta->data;
            referenced.insert(data.string());
            held += meta->bytes;
            if (path != keepMeta) entries.push_back({path, data, time, meta->bytes});
        } else {
            others.emplace_back(path, time);
        }
    }
    if (ec)
        return Error{fmt::format("{}: cannot list the remote pyramid cache: {}",
                                 m_options.folder.string(), ec.message())};
    // What a killed process left: temporary files and data no meta file names.
    const auto staleBefore = fs::file_time_type::clock::now() - kStaleAfter;
    for (const auto& [path, time] : others) {
        if (referenced.contains(path.string()) || time >= staleBefore) continue;
        if (path.extension() == kLockExtension) {
            // An entry's lock: kept while some thread or process holds it.
            const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
            const bool idle = fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0;
            if (idle) fs::remove(path, ec);
            if (fd >= 0) ::close(fd);
            continue;
        }
        fs::remove(path, ec);
    }
    if (held <= m_options.maxBytes) return held;
    std::sort(entries.begin(), entries.end(),
              [](const Entry& a, const Entry& b) { return a.used < b.used; });
    for (const Entry& e : entries) {
        if (held <= m_options.maxBytes) break;
        fs::remove(e.meta, ec);  // the meta first: a reader never finds a meta without data
        fs::remove(e.data, ec);
        held -= e.bytes;
    }
    return held;
}

}  // namespace terrain::remote
