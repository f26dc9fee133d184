#include "HostSlots.h"

#include <curl/curl.h>

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <utility>

namespace terrain::remote {
namespace {

struct Counts {
    std::mutex mutex;
    std::condition_variable freed;
    std::map<std::string, int> underWay;  // hosts with requests under way
};

Counts& counts() {
    static Counts shared;
    return shared;
}

std::string part(CURLU* parsed, CURLUPart which, unsigned flags = 0) {
    char* text = nullptr;
    if (curl_url_get(parsed, which, &text, flags) != CURLUE_OK) return {};
    std::string out(text);
    curl_free(text);
    return out;
}

}  // namespace

std::string HostSlots::hostOf(const std::string& url) {
    CURLU* parsed = curl_url();
    if (parsed == nullptr) return url;
    std::string host = url;  // unparsable: counted by itself (the request will fail anyway)
    if (curl_url_set(parsed, CURLUPART_URL, url.c_str(), 0) == CURLUE_OK) {
        host = part(parsed, CURLUPART_SCHEME) + "://" + part(parsed, CURLUPART_HOST) + ":" +
               part(parsed, CURLUPART_PORT, CURLU_DEFAULT_PORT);
    }
    curl_url_cleanup(parsed);
    return host;
}

HostSlots::Slot HostSlots::acquire(const std::string& url, int limit) {
    std::string host = hostOf(url);
    Counts& c = counts();
    std::unique_lock lock(c.mutex);
    c.freed.wait(lock, [&] { return c.underWay[host] < std::max(limit, 1); });
    ++c.underWay[host];
    return Slot(std::move(host));
}

HostSlots::Slot::Slot(Slot&& other) noexcept : m_host(std::exchange(other.m_host, {})) {}

HostSlots::Slot::~Slot() {
    if (m_host.empty()) return;
    Counts& c = counts();
    {
        std::lock_guard lock(c.mutex);
        if (--c.underWay[m_host] == 0) c.underWay.erase(m_host);
    }
    c.freed.notify_all();
}

}  // namespace terrain::remote
