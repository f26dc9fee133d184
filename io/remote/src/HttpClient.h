// HttpClient: GET of one URL, or of a range of its bytes (RFC 9110 §14), through one libcurl
// easy handle, which keeps its connection (HTTP/1.1 keep-alive, or HTTP/2 where the server
// offers it) from request to request. Failures worth retrying (no connection, a timeout or stalled
// body, a reset or a truncated body, HTTP 408, 429 and 5xx) are retried after a backoff that
// doubles each time, times a random 0.5–1.5 so that clients which failed together do not retry
// together.
#pragma once

#include "terrain/remote/RemoteFiles.h"

#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace terrain::remote {

/// What makes a GET conditional: the cached copy's validators (either may be empty).
struct Validators {
    std::string etag;
    std::string lastModified;
};

struct HttpResponse {
    long status = 0;  ///< 200 (the body is in the file) or 304 (not modified: the file is empty)
    std::string etag;
    std::string lastModified;
    std::uint64_t bytes = 0;  ///< the body's bytes written
};

namespace http {
struct Attempt;  // what one attempt saw (HttpClient.cpp)
struct Target;   // where its body goes
}  // namespace http

/// What a range GET brought: 206 with `body` holding bytes [firstByte, firstByte + size) of a
/// file of `totalBytes`; 200 with the whole file in `body` (a server that ignores ranges, or an
/// If-Range that no longer matched: the file changed); or 304 (not modified, no body).
struct RangeResponse {
    long status = 0;
    std::string etag;
    std::string lastModified;
    std::uint64_t firstByte = 0;
    std::uint64_t totalBytes = 0;
    std::string body;
};

class HttpClient {
public:
    static Result<std::unique_ptr<HttpClient>> create(const HttpOptions& options);
    ~HttpClient();
    HttpClient(const HttpClient&) = delete;
    HttpClient& operator=(const HttpClient&) = delete;

    /// GETs `url` into `file` (created or truncated for each attempt). A status other than
    /// 200 or 304 (after redirects and retries) is an Error naming the URL and the status.
    /// `stats` counts requests and retries.
    Result<HttpResponse> get(const std::string& url, const Validators& validators,
                             const std::filesystem::path& file, RemoteStats& stats);

    /// GETs bytes [first, last] of `url` (the "Range" header). `ifNoneMatch`'s validators make
    /// it conditional (a 304 when the file is unchanged); `ifRange`'s strong ETag (else its
    /// Last-Modified) asks for the range only if the file is still that version, the whole
    /// file otherwise. A status other than 200, 206 or 304, or a 206 without a Content-Range
    /// this client can read, is an Error naming the URL.
    Result<RangeResponse> getRange(const std::string& url, std::uint64_t first, std::uint64_t last,
                                   const Validators& ifNoneMatch, const Validators& ifRange,
                                   RemoteStats& stats);

    const HttpOptions& options() const { return m_options; }

private:
    struct Handle;
    // One request with its retries: the body goes to `target` (a file rewritten, or a string
    // cleared, each attempt); `accepted` tells which statuses end it.
    Result<http::Attempt> perform(const std::string& url, const std::vector<std::string>& headers,
                                  http::Target& target, bool (*accepted)(long status),
                                  RemoteStats& stats);

    HttpClient(std::unique_ptr<Handle> handle, const HttpOptions& options);

    std::unique_ptr<Handle> m_handle;
    HttpOptions m_options;
    std::mt19937 m_jitter;
};

}  // namespace terrain::remote
