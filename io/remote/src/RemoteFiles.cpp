#include "terrain/remote/RemoteFiles.h"

#include "DiskCache.h"
#include "HttpClient.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace terrain::remote {
namespace {

std::optional<std::string> environment(const char* name) {
    const char* value = std::getenv(name);
    if (value == nullptr || *value == '\0') return std::nullopt;
    return std::string(value);
}

// "4G", "512M", "100000": bytes.
std::optional<std::uint64_t> parseBytes(const std::string& text) {
    std::size_t used = 0;
    unsigned long long value = 0;
    try {
        value = std::stoull(text, &used);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    const std::string suffix = text.substr(used);
    const int shift = suffix.empty()                     ? 0
                      : suffix == "K" || suffix == "KiB" ? 10
                      : suffix == "M" || suffix == "MiB" ? 20
                      : suffix == "G" || suffix == "GiB" ? 30
                                                         : -1;
    if (shift < 0 || value > (~0ULL >> shift)) return std::nullopt;
    return std::uint64_t{value} << shift;
}

std::optional<int> parseCount(const std::string& text, int most) {
    std::size_t used = 0;
    int value = 0;
    try {
        value = std::stoi(text, &used);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    if (used != text.size() || value < 0 || value > most) return std::nullopt;
    return value;
}

}  // namespace

bool isRemoteLocation(std::string_view location) {
    const auto startsWithNoCase = [&](std::string_view prefix) {
        if (location.size() <= prefix.size()) return false;
        for (std::size_t i = 0; i < prefix.size(); ++i)
            if (std::tolower(static_cast<unsigned char>(location[i])) != prefix[i]) return false;
        return true;
    };
    return startsWithNoCase("http://") || startsWithNoCase("https://");
}

Result<std::unique_ptr<RemoteFiles>> filesFor(std::string_view location,
                                              std::shared_ptr<RemoteRun> run) {
    if (!isRemoteLocation(location)) return std::unique_ptr<RemoteFiles>{};
    return RemoteFiles::fromEnvironment(std::move(run));
}

bool RemoteRun::confirmed(const std::string& url) const {
    const std::lock_guard lock(m_mutex);
    return m_urls.contains(url);
}

void RemoteRun::confirm(const std::string& url) {
    const std::lock_guard lock(m_mutex);
    m_urls.insert(url);
}

std::optional<std::pair<std::size_t, std::size_t>> RemoteRun::claim(const std::string& url,
                                                                    std::size_t from,
                                                                    std::size_t to) {
    std::unique_lock lock(m_mutex);
    // Looked up each time: a release may remove the URL's list while this waits.
    const auto holding = [&](std::size_t block) {
        const auto found = m_claims.find(url);
        return found != m_claims.end() &&
               std::any_of(found->second.begin(), found->second.end(),
                           [&](const auto& c) { return c.first <= block && block <= c.second; });
    };
    if (holding(from)) {
        m_released.wait(lock, [&] { return !holding(from); });
        return std::nullopt;
    }
    std::vector<std::pair<std::size_t, std::size_t>>& claims = m_claims[url];
    std::size_t end = to;
    for (const auto& [first, last] : claims)
        if (first > from && first <= end) end = first - 1;
    claims.emplace_back(from, end);
    return std::pair{from, end};
}

void RemoteRun::release(const std::string& url, std::size_t from, std::size_t end) {
    {
        const std::lock_guard lock(m_mutex);
        auto found = m_claims.find(url);
        if (found != m_claims.end()) {
            std::erase(found->second, std::pair{from, end});
            if (found->second.empty()) m_claims.erase(found);
        }
    }
    m_released.notify_all();
}

std::string joinUrl(std::string_view folder, std::string_view name) {
    std::string url(folder);
    if (!url.ends_with('/')) url += '/';
    url += name;
    return url;
}

Result<CacheOptions> CacheOptions::fromEnvironment() {
    CacheOptions options;
    if (auto folder = environment("TERRAIN_CACHE_DIR")) {
        options.folder = *folder;
    } else if (auto xdg = environment("XDG_CACHE_HOME")) {
        options.folder = std::filesystem::path(*xdg) / "terrain";
    } else if (auto home = environment("HOME")) {
        options.folder = std::filesystem::path(*home) / ".cache" / "terrain";
    } else {
        return Error{
            "no folder for the remote pyramid cache: set TERRAIN_CACHE_DIR (or HOME or "
            "XDG_CACHE_HOME)"};
    }
    if (auto bytes = environment("TERRAIN_CACHE_BYTES")) {
        const std::optional<std::uint64_t> parsed = parseBytes(*bytes);
        if (!parsed)
            return Error{fmt::format(
                "TERRAIN_CACHE_BYTES=\"{}\" is not a size (bytes, or with K, M or G)", *bytes)};
        options.maxBytes = *parsed;
    }
    return options;
}

Result<HttpOptions> HttpOptions::fromEnvironment() {
    HttpOptions options;
    if (auto timeout = environment("TERRAIN_HTTP_TIMEOUT")) {
        const std::optional<int> seconds = parseCount(*timeout, 3600);
        if (!seconds || *seconds == 0)
            return Error{fmt::format(
                "TERRAIN_HTTP_TIMEOUT=\"{}\" is not a number of seconds from 1 to 3600", *timeout)};
        options.requestTimeout = std::chrono::seconds(*seconds);
        options.connectTimeout = std::min(options.connectTimeout, options.requestTimeout);
    }
    if (auto retries = environment("TERRAIN_HTTP_RETRIES")) {
        const std::optional<int> count = parseCount(*retries, 20);
        if (!count)
            return Error{fmt::format(
                "TERRAIN_HTTP_RETRIES=\"{}\" is not a count of retries from 0 to 20", *retries)};
        options.retries = *count;
    }
    if (auto perHost = environment("TERRAIN_HTTP_MAX_PER_HOST")) {
        const std::optional<int> count = parseCount(*perHost, 64);
        if (!count || *count == 0)
            return Error{fmt::format(
                "TERRAIN_HTTP_MAX_PER_HOST=\"{}\" is not a count of requests from 1 to 64",
                *perHost)};
        options.maxPerHost = *count;
    }
    if (auto range = environment("TERRAIN_HTTP_RANGE_BYTES")) {
        const std::optional<std::uint64_t> bytes = parseBytes(*range);
        if (!bytes || *bytes % kCacheBlockBytes != 0 || *bytes > (std::uint64_t{1} << 30))
            return Error{fmt::format(
                "TERRAIN_HTTP_RANGE_BYTES=\"{}\" is not 0 or a multiple of 16K up to 1G", *range)};
        options.rangeBytes = *bytes;
    }
    return options;
}

RemoteFiles::RemoteFiles(std::unique_ptr<DiskCache> cache, std::unique_ptr<HttpClient> http,
                         std::shared_ptr<RemoteRun> run)
    : m_cache(std::move(cache)),
      m_http(std::move(http)),
      m_run(run ? std::move(run) : std::make_shared<RemoteRun>()) {}

RemoteFiles::~RemoteFiles() = default;

Result<std::unique_ptr<RemoteFiles>> RemoteFiles::open(const CacheOptions& cache,
                                                       const HttpOptions& http,
                                                       std::shared_ptr<RemoteRun> run) {
    Result<std::unique_ptr<DiskCache>> disk = DiskCache::open(cache);
    if (!disk) return disk.error();
    Result<std::unique_ptr<HttpClient>> client = HttpClient::create(http);
    if (!client) return client.error();
    return std::unique_ptr<RemoteFiles>(
        new RemoteFiles(std::move(disk).value(), std::move(client).value(), std::move(run)));
}

Result<std::unique_ptr<RemoteFiles>> RemoteFiles::fromEnvironment(std::shared_ptr<RemoteRun> run) {
    Result<CacheOptions> cache = CacheOptions::fromEnvironment();
    if (!cache) return cache.error();
    Result<HttpOptions> http = HttpOptions::fromEnvironment();
    if (!http) return http.error();
    return open(cache.value(), http.value(), std::move(run));
}

void RemoteFiles::used(const std::string& url, std::uint64_t& outcome) {
    ++outcome;
    m_run->confirm(url);
    m_cache->touch(url);
}

Error RemoteFiles::notModifiedWithoutCopy(const std::string& url) {
    // A 304 to an unconditional GET: a broken server or proxy.
    return Error{
        fmt::format("{}: the server answered 304 (not modified) to a request for a "
                    "file this cache does not have",
                    url)};
}

Result<std::filesystem::path> RemoteFiles::localCopy(const std::string& url) {
    std::optional<CachedFile> cached = m_cache->find(url);
    if (cached && m_run->confirmed(url)) {
        used(url, m_stats.cacheHits);
        return cached->data;
    }
    // One fetch or confirmation of a URL at a time among the cache's users, threads and
    // processes alike (request coalescing): who waited for the entry's lock finds the copy
    // the holder fetched, confirmed or used meanwhile, and takes it as confirmed.
    const std::filesystem::file_time_type waitStart = std::filesystem::file_time_type::clock::now();
    Result<EntryLock> lock = m_cache->lockEntry(url);
    if (!lock) return lock.error();
    cached = m_cache->find(url);
    if (cached && cached->used >= waitStart) {
        ++m_stats.cacheHits;
        m_run->confirm(url);
        return cached->data;
    }
    Result<AtomicFile> body = m_cache->reserve(url);
    if (!body) return body.error();
    Validators validators;
    if (cached) validators = {cached->etag, cached->lastModified};
    Result<HttpResponse> response =
        m_http->get(url, validators, body.value().temporaryPath(), m_stats);
    if (!response) {
        if (cached) {  // offline, or the server is down: the copy we have beats nothing
            used(url, m_stats.staleServed);
            return cached->data;
        }
        return response.error();
    }
    if (response.value().status == 304) {
        if (!cached) return notModifiedWithoutCopy(url);
        used(url, m_stats.notModified);
        return cached->data;
    }
    ++m_stats.fetched;
    m_stats.fetchedBytes += response.value().bytes;
    Result<CachedFile> stored =
        m_cache->store(url, std::move(body).value(), response.value().etag,
                       response.value().lastModified, response.value().bytes);
    if (!stored) return stored.error();
    m_run->confirm(url);
    return stored.value().data;
}

Result<std::unique_ptr<RemoteFile>> RemoteFiles::openEntry(const std::string& url,
                                                           PartialFile entry) {
    const int fd = ::open(entry.data.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0)
        return Error{fmt::format("{}: cannot open its cache entry {}: {}", url, entry.data.string(),
                                 std::strerror(errno))};
    return std::unique_ptr<RemoteFile>(
        new RemoteFile(*this, url, std::make_unique<PartialFile>(std::move(entry)), fd));
}

Result<std::unique_ptr<RemoteFile>> RemoteFiles::keepWhole(const std::string& url,
                                                           const std::string& body,
                                                           const std::string& etag,
                                                           const std::string& lastModified) {
    Result<AtomicFile> file = m_cache->reserve(url);
    if (!file) return file.error();
    {
        std::ofstream out(file.value().temporaryPath(), std::ios::binary | std::ios::trunc);
        out.write(body.data(), static_cast<std::streamsize>(body.size()));
        out.close();
        if (!out)
            return Error{fmt::format("{}: cannot keep it in the cache: cannot write {}", url,
                                     file.value().temporaryPath().string())};
    }
    Result<CachedFile> stored =
        m_cache->store(url, std::move(file).value(), etag, lastModified, body.size());
    if (!stored) return stored.error();
    m_run->confirm(url);
    const CachedFile& whole = stored.value();
    return openEntry(url,
                     PartialFile{whole.data, etag, lastModified, whole.bytes,
                                 std::vector<bool>(blocksOfFile(whole.bytes), true), whole.used});
}

Result<std::unique_ptr<RemoteFile>> RemoteFiles::openRanged(const std::string& url) {
    const std::uint64_t rangeBytes = m_http->options().rangeBytes;
    if (rangeBytes == 0) {  // whole, as any other file
        Result<std::filesystem::path> copy = localCopy(url);
        if (!copy) return copy.error();
        std::optional<PartialFile> whole = m_cache->findPartial(url);
        if (!whole || whole->data != copy.value())
            return Error{fmt::format("{}: its copy left the cache as it came", url)};
        return openEntry(url, std::move(*whole));
    }
    std::optional<PartialFile> cached = m_cache->findPartial(url);
    if (cached && m_run->confirmed(url)) {
        used(url, m_stats.cacheHits);
        return openEntry(url, std::move(*cached));
    }
    // As in localCopy: one confirmation or first fetch of a URL at a time among the cache's
    // users; who waited uses what the holder found.
    const std::filesystem::file_time_type waitStart = std::filesystem::file_time_type::clock::now();
    Result<EntryLock> lock = m_cache->lockEntry(url);
    if (!lock) return lock.error();
    cached = m_cache->findPartial(url);
    if (cached && cached->used >= waitStart) {
        ++m_stats.cacheHits;
        m_run->confirm(url);
        return openEntry(url, std::move(*cached));
    }
    Validators validators;
    if (cached) validators = {cached->etag, cached->lastModified};
    Result<RangeResponse> first = m_http->getRange(url, 0, rangeBytes - 1, validators, {}, m_stats);
    if (!first) {
        if (cached) {  // offline, or the server is down: the blocks we have beat nothing
            used(url, m_stats.staleServed);
            return openEntry(url, std::move(*cached));
        }
        return first.error();
    }
    RangeResponse& head = first.value();
    if (head.status == 304) {
        if (!cached) return notModifiedWithoutCopy(url);
        used(url, m_stats.notModified);
        return openEntry(url, std::move(*cached));
    }
    ++m_stats.fetched;
    m_stats.fetchedBytes += head.body.size();
    if (head.status == 200 || head.body.size() == head.totalBytes)
        return keepWhole(url, head.body, head.etag, head.lastModified);
    if (head.firstByte != 0)
        return Error{fmt::format("{}: asked for its first bytes, the server sent bytes from {}",
                                 url, head.firstByte)};
    if (head.totalBytes <= m_http->options().wholeFileBytes()) {  // small: the rest at once
        Result<RangeResponse> rest = m_http->getRange(url, head.body.size(), head.totalBytes - 1,
                                                      {}, {head.etag, head.lastModified}, m_stats);
        if (!rest) return rest.error();
        ++m_stats.fetched;
        m_stats.fetchedBytes += rest.value().body.size();
        if (rest.value().status == 200)  // changed meanwhile: the new version, whole
            return keepWhole(url, rest.value().body, rest.value().etag, rest.value().lastModified);
        if (rest.value().status != 206 || rest.value().firstByte != head.body.size() ||
            head.body.size() + rest.value().body.size() != head.totalBytes)
            return Error{
                fmt::format("{}: the server sent another part of the file than asked", url)};
        return keepWhole(url, head.body + rest.value().body, head.etag, head.lastModified);
    }
    Result<PartialFile> started =
        m_cache->startPartial(url, head.etag, head.lastModified, head.totalBytes);
    if (!started) return started.error();
    m_run->confirm(url);
    Result<std::unique_ptr<RemoteFile>> opened = openEntry(url, std::move(started).value());
    if (!opened) return opened.error();
    RemoteFile& file = *opened.value();
    // The head is whole blocks (rangeBytes is a multiple of a block) of a larger file.
    if (::pwrite(file.m_fd, head.body.data(), head.body.size(), 0) !=
        static_cast<ssize_t>(head.body.size()))
        return Error{
            fmt::format("{}: cannot write its cache entry: {}", url, std::strerror(errno))};
    const std::size_t headBlocks = blocksOfFile(head.body.size());
    for (std::size_t b = 0; b < headBlocks; ++b) file.m_entry->blocks[b] = true;
    file.m_fetchBlocks = headBlocks;  // the head was a fetch: reading on from it grows the next
    file.m_fetchEnd = headBlocks;
    if (auto recorded = m_cache->recordBlocks(url, *file.m_entry)) file.m_entry->blocks = *recorded;
    return opened;
}

RemoteFile::RemoteFile(RemoteFiles& files, std::string url, std::unique_ptr<PartialFile> entry,
                       int fd)
    : m_files(files), m_url(std::move(url)), m_entry(std::move(entry)), m_fd(fd) {}

RemoteFile::~RemoteFile() {
    if (m_fd >= 0) ::close(m_fd);
}

std::uint64_t RemoteFile::size() const { return m_entry->size; }

Status RemoteFile::read(std::uint64_t offset, std::span<char> out) {
    if (out.empty()) return {};
    if (offset > m_entry->size || out.size() > m_entry->size - offset)
        return Error{fmt::format("{}: bytes {} to {} are beyond its end ({} bytes)", m_url, offset,
                                 offset + out.size(), m_entry->size)};
    const std::size_t first = static_cast<std::size_t>(offset / kCacheBlockBytes);
    const std::size_t last = static_cast<std::size_t>((offset + out.size() - 1) / kCacheBlockBytes);
    const auto allThere = [&] {
        for (std::size_t b = first; b <= last; ++b)
            if (!m_entry->blocks[b]) return false;
        return true;
    };
    if (!allThere()) {
        bool fetchedAny = false;
        while (true) {
            // Another reader (thread or process) may have fetched them meanwhile.
            if (std::optional<PartialFile> now = m_files.m_cache->findPartial(m_url);
                now && now->data == m_entry->data)
                for (std::size_t b = 0; b < m_entry->blocks.size(); ++b)
                    m_entry->blocks[b] = m_entry->blocks[b] || now->blocks[b];
            if (allThere()) break;
            Result<bool> fetched = fetch(first, last);
            if (!fetched) return fetched.error();
            fetchedAny = fetchedAny || fetched.value();
        }
        if (!fetchedAny) ++m_files.m_stats.cacheHits;  // another reader's fetch served it
    }
    for (std::size_t done = 0; done < out.size();) {
        const ssize_t n =
            ::pread(m_fd, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
        if (n <= 0)
            return Error{fmt::format("{}: cannot read its cache entry {}: {}", m_url,
                                     m_entry->data.string(),
                                     n == 0 ? "shorter than recorded" : std::strerror(errno))};
        done += static_cast<std::size_t>(n);
    }
    return {};
}

Result<bool> RemoteFile::fetch(std::size_t firstBlock, std::size_t lastBlock) {
    std::vector<bool>& blocks = m_entry->blocks;
    // From the first missing block, at least a fetch's worth, up to the next block that is
    // there. A fetch's worth starts at rangeBytes and doubles while reads land within one
    // fetch's worth after the last fetch's end (a reader going through the file: as GDAL's
    // /vsicurl/ grows its reads), up to kMaxFetchBlocks; a read elsewhere starts over.
    std::size_t from = firstBlock;
    while (blocks[from]) ++from;
    const std::size_t base =
        static_cast<std::size_t>(m_files.m_http->options().rangeBytes / kCacheBlockBytes);
    const bool onward =
        m_fetchBlocks > 0 && from >= m_fetchEnd && from < m_fetchEnd + m_fetchBlocks;
    const std::size_t worth =
        onward ? std::min(2 * m_fetchBlocks, std::max(base, kMaxFetchBlocks)) : base;
    std::size_t to = std::max(lastBlock, from + worth - 1);
    to = std::min(to, blocks.size() - 1);
    for (std::size_t b = lastBlock + 1; b <= to; ++b)
        if (blocks[b]) {
            to = b - 1;
            break;
        }
    // Up to the first block another reader of this run is fetching; if that is the first,
    // wait for it and look again.
    const std::optional<std::pair<std::size_t, std::size_t>> claimed =
        m_files.m_run->claim(m_url, from, to);
    if (!claimed) return false;
    to = claimed->second;
    struct Release {
        RemoteRun& run;
        const std::string& url;
        std::size_t from, to;
        ~Release() { run.release(url, from, to); }
    } release{*m_files.m_run, m_url, from, to};
    m_fetchBlocks = worth;
    const std::uint64_t firstByte = from * kCacheBlockBytes;
    const std::uint64_t lastByte = std::min<std::uint64_t>((to + 1) * kCacheBlockBytes, size()) - 1;
    // Blocks between the first and the last wanted that are there already come again: one
    // request, not several.
    Result<RangeResponse> got = m_files.m_http->getRange(
        m_url, firstByte, lastByte, {}, {m_entry->etag, m_entry->lastModified}, m_files.m_stats);
    if (!got) return got.error();
    const RangeResponse& r = got.value();
    if (r.status == 200)
        return Error{fmt::format(
            "{}: the file changed on the server while it was being read (run again)", m_url)};
    if (r.status != 206 || r.firstByte != firstByte || r.body.size() != lastByte - firstByte + 1 ||
        r.totalBytes != size())
        return Error{
            fmt::format("{}: asked for bytes {} to {} of {}, the server answered {} with {} bytes "
                        "from {} of {}",
                        m_url, firstByte, lastByte, size(), r.status, r.body.size(), r.firstByte,
                        r.totalBytes)};
    ++m_files.m_stats.fetched;
    m_files.m_stats.fetchedBytes += r.body.size();
    // Written and recorded under the entry's lock: the meta's blocks are read, merged and
    // replaced by one writer at a time.
    Result<EntryLock> lock = m_files.m_cache->lockEntry(m_url);
    if (!lock) return lock.error();
    if (::pwrite(m_fd, r.body.data(), r.body.size(), static_cast<off_t>(firstByte)) !=
        static_cast<ssize_t>(r.body.size()))
        return Error{fmt::format("{}: cannot write its cache entry {}: {}", m_url,
                                 m_entry->data.string(), std::strerror(errno))};
    for (std::size_t b = from; b <= to; ++b) blocks[b] = true;
    m_fetchEnd = to + 1;
    if (auto recorded = m_files.m_cache->recordBlocks(m_url, *m_entry)) blocks = *recorded;
    return true;
}

}  // namespace terrain::remote
