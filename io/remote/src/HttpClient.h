// HttpClient: GET of one URL into a file through one libcurl easy handle, which keeps its
// connection (HTTP/1.1 keep-alive, or HTTP/2 where the server offers it) from request to
// request. Failures worth retrying (no connection, a timeout or stalled body, a reset or a
// truncated body, HTTP 408, 429 and 5xx) are retried after a backoff that doubles each time,
// times a random 0.5–1.5 so that clients which failed together do not retry together.
#pragma once

#include "terrain/remote/RemoteFiles.h"

#include <filesystem>
#include <memory>
#include <random>
#include <string>

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

private:
    struct Handle;
    HttpClient(std::unique_ptr<Handle> handle, const HttpOptions& options);

    std::unique_ptr<Handle> m_handle;
    HttpOptions m_options;
    std::mt19937 m_jitter;
};

}  // namespace terrain::remote
