#include "terrain/remote/RemoteFiles.h"

#include "DiskCache.h"
#include "HttpClient.h"

#include <fmt/format.h>

#include <cctype>
#include <cstdlib>

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

Result<std::unique_ptr<RemoteFiles>> filesFor(std::string_view location) {
    if (!isRemoteLocation(location)) return std::unique_ptr<RemoteFiles>{};
    return RemoteFiles::fromEnvironment();
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
    return options;
}

RemoteFiles::RemoteFiles(std::unique_ptr<DiskCache> cache, std::unique_ptr<HttpClient> http)
    : m_cache(std::move(cache)), m_http(std::move(http)) {}

RemoteFiles::~RemoteFiles() = default;

Result<std::unique_ptr<RemoteFiles>> RemoteFiles::open(const CacheOptions& cache,
                                                       const HttpOptions& http) {
    Result<std::unique_ptr<DiskCache>> disk = DiskCache::open(cache);
    if (!disk) return disk.error();
    Result<std::unique_ptr<HttpClient>> client = HttpClient::create(http);
    if (!client) return client.error();
    return std::unique_ptr<RemoteFiles>(
        new RemoteFiles(std::move(disk).value(), std::move(client).value()));
}

Result<std::unique_ptr<RemoteFiles>> RemoteFiles::fromEnvironment() {
    Result<CacheOptions> cache = CacheOptions::fromEnvironment();
    if (!cache) return cache.error();
    Result<HttpOptions> http = HttpOptions::fromEnvironment();
    if (!http) return http.error();
    return open(cache.value(), http.value());
}

Result<std::filesystem::path> RemoteFiles::localCopy(const std::string& url) {
    std::optional<CachedFile> cached = m_cache->find(url);
    if (cached && m_checked.contains(url)) {
        ++m_stats.cacheHits;
        m_cache->touch(url);
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
        m_checked.insert(url);
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
            ++m_stats.staleServed;
            m_checked.insert(url);
            m_cache->touch(url);
            return cached->data;
        }
        return response.error();
    }
    if (response.value().status == 304) {
        if (!cached)  // a 304 to an unconditional GET: a broken server or proxy
            return Error{
                fmt::format("{}: the server answered 304 (not modified) to a request "
                            "for a file this cache does not have",
                            url)};
        ++m_stats.notModified;
        m_checked.insert(url);
        m_cache->touch(url);
        return cached->data;
    }
    ++m_stats.fetched;
    m_stats.fetchedBytes += response.value().bytes;
    Result<CachedFile> stored =
        m_cache->store(url, std::move(body).value(), response.value().etag,
                       response.value().lastModified, response.value().bytes);
    if (!stored) return stored.error();
    m_checked.insert(url);
    return stored.value().data;
}

}  // namespace terrain::remote
