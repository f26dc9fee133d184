#include "HttpClient.h"

#include "HostSlots.h"

#include <curl/curl.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <thread>

namespace terrain::remote {

// What one attempt saw.
struct http::Attempt {
    CURLcode code = CURLE_OK;
    long status = 0;
    std::string etag;
    std::string lastModified;
    std::string contentRange;  // "bytes 0-99/1234" of a 206
    std::uint64_t bytes = 0;
    bool writeFailed = false;
    std::string curlMessage;
};

// Where an attempt's body goes: a file (created or truncated for each attempt) or a string
// (cleared for each attempt).
struct http::Target {
    std::filesystem::path file;
    std::string* memory = nullptr;
};

namespace {
using http::Attempt;
using http::Target;

// curl_global_init is not thread-safe in every libcurl; once per process, before any handle.
void initialiseCurlOnce() {
    static std::once_flag once;
    std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

std::string trimmed(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return std::string(s);
}

// The value of header line `line` if its name is `name` (case-insensitive).
std::optional<std::string> headerValue(std::string_view line, std::string_view name) {
    if (line.size() <= name.size() || line[name.size()] != ':') return std::nullopt;
    for (std::size_t i = 0; i < name.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(line[i])) !=
            std::tolower(static_cast<unsigned char>(name[i])))
            return std::nullopt;
    return trimmed(line.substr(name.size() + 1));
}

std::size_t onHeader(char* data, std::size_t size, std::size_t count, void* user) {
    auto& attempt = *static_cast<Attempt*>(user);
    const std::string_view line(data, size * count);
    // A new response (a redirect's, or a 100 Continue's) starts over.
    if (line.starts_with("HTTP/")) {
        attempt.etag.clear();
        attempt.lastModified.clear();
        attempt.contentRange.clear();
    } else if (auto range = headerValue(line, "content-range")) {
        attempt.contentRange = *range;
    } else if (auto etag = headerValue(line, "etag")) {
        attempt.etag = *etag;
    } else if (auto modified = headerValue(line, "last-modified")) {
        attempt.lastModified = *modified;
    }
    return size * count;
}

struct BodySink {
    std::FILE* file = nullptr;
    std::string* memory = nullptr;
    Attempt* attempt = nullptr;
};

std::size_t onBody(char* data, std::size_t size, std::size_t count, void* user) {
    auto& sink = *static_cast<BodySink*>(user);
    const std::size_t n = size * count;
    if (sink.memory != nullptr) {
        sink.memory->append(data, n);
    } else if (std::fwrite(data, 1, n, sink.file) != n) {
        sink.attempt->writeFailed = true;
        return 0;  // ends the transfer with CURLE_WRITE_ERROR
    }
    sink.attempt->bytes += n;
    return n;
}

bool worthRetrying(const Attempt& a) {
    if (a.writeFailed) return false;  // the local disk, not the network
    switch (a.code) {
        case CURLE_OK:
            return a.status == 408 || a.status == 429 || a.status >= 500;
        case CURLE_URL_MALFORMAT:
        case CURLE_UNSUPPORTED_PROTOCOL:
        case CURLE_TOO_MANY_REDIRECTS:
        case CURLE_OUT_OF_MEMORY:
            return false;
        default:  // no connection, timeouts, resets, truncated bodies, TLS hiccups
            return true;
    }
}

std::string describe(const Attempt& a) {
    if (a.writeFailed) return fmt::format("cannot write the body to the cache: {}", a.curlMessage);
    if (a.code != CURLE_OK)
        return a.curlMessage.empty() ? std::string(curl_easy_strerror(a.code)) : a.curlMessage;
    const char* meaning = a.status == 404   ? " (not found)"
                          : a.status == 403 ? " (forbidden)"
                          : a.status == 401 ? " (unauthorised)"
                          : a.status >= 500 ? " (server error)"
                                            : "";
    return fmt::format("HTTP {}{}", a.status, meaning);
}

}  // namespace

struct HttpClient::Handle {
    CURL* curl = nullptr;
    ~Handle() {
        if (curl != nullptr) curl_easy_cleanup(curl);
    }
};

HttpClient::HttpClient(std::unique_ptr<Handle> handle, const HttpOptions& options)
    : m_handle(std::move(handle)), m_options(options), m_jitter(std::random_device{}()) {}

HttpClient::~HttpClient() = default;

Result<std::unique_ptr<HttpClient>> HttpClient::create(const HttpOptions& options) {
    initialiseCurlOnce();
    auto handle = std::make_unique<Handle>();
    handle->curl = curl_easy_init();
    if (handle->curl == nullptr) return Error{"libcurl could not make a transfer handle"};
    return std::unique_ptr<HttpClient>(new HttpClient(std::move(handle), options));
}

Result<HttpResponse> HttpClient::get(const std::string& url, const Validators& validators,
                                     const std::filesystem::path& file, RemoteStats& stats) {
    std::vector<std::string> headers;
    if (!validators.etag.empty()) headers.push_back("If-None-Match: " + validators.etag);
    if (!validators.lastModified.empty())
        headers.push_back("If-Modified-Since: " + validators.lastModified);
    Target target{file, nullptr};
    Result<Attempt> done = perform(
        url, headers, target, [](long status) { return status == 200 || status == 304; }, stats);
    if (!done) return done.error();
    const Attempt& a = done.value();
    return HttpResponse{a.status, a.etag, a.lastModified, a.bytes};
}

namespace {

// "bytes FIRST-LAST/TOTAL" (RFC 9110 §14.4) as its three numbers; nullopt for anything else,
// "bytes */TOTAL" and an unknown total ("/*") included.
std::optional<std::array<std::uint64_t, 3>> parseContentRange(std::string_view text) {
    if (!text.starts_with("bytes ")) return std::nullopt;
    text.remove_prefix(6);
    std::array<std::uint64_t, 3> values{};
    const char separators[] = {'-', '/', '\0'};
    for (std::size_t i = 0; i < 3; ++i) {
        const auto [end, error] =
            std::from_chars(text.data(), text.data() + text.size(), values[i]);
        if (error != std::errc{} || end == text.data()) return std::nullopt;
        text.remove_prefix(static_cast<std::size_t>(end - text.data()));
        if (i < 2) {
            if (text.empty() || text.front() != separators[i]) return std::nullopt;
            text.remove_prefix(1);
        }
    }
    if (!text.empty() || values[1] < values[0] || values[1] >= values[2]) return std::nullopt;
    return values;
}

}  // namespace

Result<RangeResponse> HttpClient::getRange(const std::string& url, std::uint64_t first,
                                           std::uint64_t last, const Validators& ifNoneMatch,
                                           const Validators& ifRange, RemoteStats& stats) {
    std::vector<std::string> headers{fmt::format("Range: bytes={}-{}", first, last)};
    if (!ifNoneMatch.etag.empty()) headers.push_back("If-None-Match: " + ifNoneMatch.etag);
    if (!ifNoneMatch.lastModified.empty())
        headers.push_back("If-Modified-Since: " + ifNoneMatch.lastModified);
    // If-Range takes one validator, and a weak ETag never matches it (RFC 9110 §13.1.5): a
    // strong ETag, which two versions within a second cannot share, else the date.
    if (!ifRange.etag.empty() && !ifRange.etag.starts_with("W/"))
        headers.push_back("If-Range: " + ifRange.etag);
    else if (!ifRange.lastModified.empty())
        headers.push_back("If-Range: " + ifRange.lastModified);
    RangeResponse response;
    Target target{{}, &response.body};
    Result<Attempt> done = perform(
        url, headers, target,
        [](long status) { return status == 200 || status == 206 || status == 304; }, stats);
    if (!done) return done.error();
    const Attempt& a = done.value();
    response.status = a.status;
    response.etag = a.etag;
    response.lastModified = a.lastModified;
    if (a.status == 200) {
        response.totalBytes = response.body.size();
    } else if (a.status == 206) {
        const auto range = parseContentRange(a.contentRange);
        if (!range || range->at(1) - range->at(0) + 1 != response.body.size())
            return Error{fmt::format(
                "{}: the server answered a range request with Content-Range \"{}\" and {} "
                "bytes, which do not agree",
                url, a.contentRange, response.body.size())};
        response.firstByte = range->at(0);
        response.totalBytes = range->at(2);
    }
    return response;
}

Result<Attempt> HttpClient::perform(const std::string& url,
                                    const std::vector<std::string>& headerLines, Target& target,
                                    bool (*accepted)(long status), RemoteStats& stats) {
    CURL* curl = m_handle->curl;
    struct HeaderList {
        curl_slist* list = nullptr;
        ~HeaderList() { curl_slist_free_all(list); }
    } headers;
    for (const std::string& line : headerLines)
        headers.list = curl_slist_append(headers.list, line.c_str());

    char errorText[CURL_ERROR_SIZE] = {};
    std::chrono::milliseconds backoff = m_options.firstBackoff;
    Attempt attempt;
    for (int tries = 0;; ++tries) {
        attempt = Attempt{};
        std::unique_ptr<std::FILE, FileCloser> out;
        if (target.memory != nullptr) {
            target.memory->clear();
        } else {
            out.reset(std::fopen(target.file.c_str(), "wb"));
            if (!out)
                return Error{fmt::format("{}: cannot write {}: {}", url, target.file.string(),
                                         std::strerror(errno))};
        }
        BodySink sink{out.get(), target.memory, &attempt};
        errorText[0] = '\0';
        curl_easy_reset(curl);  // keeps the connection cache: keep-alive survives
        curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
        curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L);
        curl_easy_setopt(curl, CURLOPT_FOLLOWLOCATION, 1L);
        curl_easy_setopt(curl, CURLOPT_MAXREDIRS, 5L);
        curl_easy_setopt(curl, CURLOPT_HTTP_VERSION, long{CURL_HTTP_VERSION_2TLS});
        curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS,
                         static_cast<long>(m_options.connectTimeout.count()));
        curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS,
                         static_cast<long>(m_options.requestTimeout.count()));
        curl_easy_setopt(curl, CURLOPT_LOW_SPEED_LIMIT, 1024L);
        curl_easy_setopt(curl, CURLOPT_LOW_SPEED_TIME, 10L);
        curl_easy_setopt(curl, CURLOPT_HTTPHEADER, headers.list);
        curl_easy_setopt(curl, CURLOPT_ERRORBUFFER, errorText);
        curl_easy_setopt(curl, CURLOPT_HEADERFUNCTION, onHeader);
        curl_easy_setopt(curl, CURLOPT_HEADERDATA, &attempt);
        curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, onBody);
        curl_easy_setopt(curl, CURLOPT_WRITEDATA, &sink);
        ++stats.requests;
        if (tries > 0) ++stats.retries;
        {
            const HostSlots::Slot slot = HostSlots::acquire(url, m_options.maxPerHost);
            attempt.code = curl_easy_perform(curl);
        }
        curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &attempt.status);
        if (out && attempt.code == CURLE_OK && accepted(attempt.status)) {
            // A body shorter than its Content-Length is CURLE_PARTIAL_FILE above; a write
            // error of the last bytes shows only when the file is closed.
            if (std::fflush(out.get()) != 0 || std::ferror(out.get()) != 0) {
                attempt.writeFailed = true;
                attempt.curlMessage = std::strerror(errno);
            }
        }
        attempt.curlMessage = attempt.curlMessage.empty() ? errorText : attempt.curlMessage;
        out.reset();
        const bool ok =
            attempt.code == CURLE_OK && !attempt.writeFailed && accepted(attempt.status);
        if (ok) break;
        if (!worthRetrying(attempt) || tries >= m_options.retries)
            return Error{fmt::format("{}: {}{}", url, describe(attempt),
                                     tries > 0 ? fmt::format(" ({} attempts)", tries + 1) : "")};
        std::uniform_real_distribution<double> jitter(0.5, 1.5);
        std::this_thread::sleep_for(
            std::chrono::duration_cast<std::chrono::milliseconds>(backoff * jitter(m_jitter)));
        backoff *= 2;
    }
    return attempt;
}

}  // namespace terrain::remote
