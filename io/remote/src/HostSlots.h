// HostSlots: the per-host concurrency limit of a process's HTTP requests (issue 49). Every
// HttpClient (one per reader thread, per RemoteFiles) takes a slot for its URL's host before
// a transfer and gives it back after, so however many readers a process runs, at most
// HttpOptions::maxPerHost requests go to one server at once, as browsers and GDAL's
// /vsicurl/ keep to (object stores throttle clients that open more).
#pragma once

#include <string>

namespace terrain::remote {

class HostSlots {
public:
    /// A slot held: given back when it goes.
    class Slot {
    public:
        Slot(Slot&& other) noexcept;
        Slot& operator=(Slot&&) = delete;
        Slot(const Slot&) = delete;
        Slot& operator=(const Slot&) = delete;
        ~Slot();

    private:
        friend class HostSlots;
        explicit Slot(std::string host) : m_host(std::move(host)) {}
        std::string m_host;  // empty once moved from
    };

    /// Waits until fewer than `limit` (≥ 1) of this process's requests to `url`'s host are
    /// under way, and takes a slot.
    static Slot acquire(const std::string& url, int limit);
    /// "scheme://host:port" of `url` (the port made explicit), what slots are counted by.
    static std::string hostOf(const std::string& url);
};

}  // namespace terrain::remote
