// FaultProxy: an HTTP/1.1 proxy on 127.0.0.1 that a test puts between a client and a real
// server (NginxServer.h) to make the network misbehave on purpose (issue 49): a latency before
// every response, and on a fixed schedule of requests a reset connection, a connection closed
// without an answer, a 503, a body cut short, a body trickled out slowly, or a body held half
// sent until the test releases it (to kill a client mid-write); and packet loss, TCP's way:
// each segment of an answer (and each request) lost with a given probability stalls the
// stream behind it until it is sent again (FaultPlan::segmentLoss), nothing else lost; and
// TCP's congestion window, so a large answer takes round trips (FaultPlan::initialWindow).
//
// Deterministic by request count, not by chance: request n (1-based, in the order they reach
// the proxy) is faulted when n is a multiple of `faultEvery` (and, by default, its path was
// not faulted before), with the plan's kinds taken in turn, fault after fault. So a run that
// faults as many requests as there are kinds meets every kind, whatever the threads' timing
// (with faultEvery = 1, the first request of each of that many paths); which file a fault lands on
// may vary, and what is tested is that the client copes with each.
//
// Each request is forwarded on its own upstream connection ("Connection: close"), read whole,
// then answered on the client's connection, which stays open for the next request
// (keep-alive) unless the fault closes it.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace terrain::test {

enum class ProxyFault {
    None,
    Reset,        ///< the connection reset (RST) instead of an answer
    Drop,         ///< the connection closed (FIN) instead of an answer
    ServerError,  ///< "503 Service Unavailable", the connection kept
    Truncated,    ///< the headers and half the body, then the connection closed
    SlowBody,     ///< the whole body in eight pieces, 25 ms apart
    HoldBody,     ///< the headers and half the body, then nothing until release()
};

struct FaultPlan {
    /// Waited before each answer (a round trip's worth of delay).
    std::chrono::milliseconds latency{0};
    /// Every faultEvery-th request is faulted (0: none).
    int faultEvery = 0;
    /// Whether a path is faulted once at most, so that a client's first retry of it gets
    /// through whatever the other threads' requests interleave: the outcome of a run is then
    /// deterministic (every file arrives, a retry later) though which files meet faults is not.
    bool oncePerPath = true;
    /// The faults, in turn.
    std::vector<ProxyFault> kinds = {ProxyFault::Reset, ProxyFault::Drop, ProxyFault::ServerError,
                                     ProxyFault::Truncated, ProxyFault::SlowBody};
    /// Packet loss: the probability that a request, or a segment of an answer (kSegmentBytes,
    /// an Ethernet frame's TCP payload), is lost. TCP delivers nothing beyond a lost segment
    /// until it is sent again, so each loss stalls the stream: for a round trip (`latency`)
    /// where three or more segments follow it (their duplicate acknowledgements make the
    /// sender retransmit at once, RFC 5681's fast retransmit), else for retransmitDelay,
    /// Linux's least retransmission timeout (a request's loss, or one near a transfer's end).
    /// Drawn from a hash of the request's number and the segment's, so a run's losses depend
    /// on the order requests arrive in only.
    double segmentLoss = 0.0;
    std::chrono::milliseconds retransmitDelay{200};
    /// TCP's congestion window, in segments, as a connection starts and after it has been
    /// idle longer than retransmitDelay (RFC 5681 §4.1; Linux's slow start after idle); 0:
    /// none, an answer goes out at once. With one, an answer goes out a window at a time, a
    /// round trip (`latency`) between windows while the acknowledgements come back; the window
    /// doubles each round trip (slow start) up to the threshold, then grows by a segment, and a
    /// round with a loss halves it and sets the threshold there (Reno). Linux starts at 10
    /// (RFC 6928).
    std::size_t initialWindow = 0;
    /// The user's link, in bytes a second, shared by every connection: a segment goes out
    /// when the link has sent those before it (one queue, serialised at this rate, as at a
    /// home line's bottleneck); 0: no cap. Applies to answers sent a window at a time.
    double linkBytesPerSecond = 0.0;
    static constexpr std::size_t kSegmentBytes = 1448;
};

class FaultProxy {
public:
    FaultProxy(int upstreamPort, FaultPlan plan = {})
        : m_upstreamPort(upstreamPort), m_plan(std::move(plan)) {
        m_listener = ::socket(AF_INET, SOCK_STREAM, 0);
        const int one = 1;
        ::setsockopt(m_listener, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
        sockaddr_in address = loopback(0);
        socklen_t length = sizeof(address);
        if (::bind(m_listener, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
            ::listen(m_listener, 64) != 0 ||
            ::getsockname(m_listener, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
            ::close(m_listener);
            m_listener = -1;
            return;
        }
        m_port = ntohs(address.sin_port);
        m_acceptor = std::thread([this] { acceptLoop(); });
    }

    ~FaultProxy() {
        m_stopping = true;
        release();
        if (m_listener >= 0) ::shutdown(m_listener, SHUT_RDWR);
        {
            std::lock_guard lock(m_mutex);
            for (int fd : m_clients) ::shutdown(fd, SHUT_RDWR);
        }
        if (m_acceptor.joinable()) m_acceptor.join();
        for (std::thread& t : m_connections) t.join();
        if (m_listener >= 0) ::close(m_listener);
    }
    FaultProxy(const FaultProxy&) = delete;
    FaultProxy& operator=(const FaultProxy&) = delete;

    bool ready() const { return m_port > 0; }
    /// "http://127.0.0.1:<port>/" + path.
    std::string url(const std::string& path) const {
        return "http://127.0.0.1:" + std::to_string(m_port) + "/" + path;
    }

    /// Requests that reached the proxy so far.
    int requests() const { return m_requests.load(); }
    /// Packets (requests and answers' segments) lost so far (FaultPlan::segmentLoss).
    int lostPackets() const { return m_lostPackets.load(); }
    /// The most requests it was answering at once so far: a request counts from its head's
    /// arrival until just before the client sees anything of the answer, so a client that
    /// waits for its answer before sending the next request never counts twice.
    int maxInFlight() const { return m_maxInFlight.load(); }
    /// How many requests met each fault so far (a HoldBody counts once its half body is sent).
    int faulted(ProxyFault kind) const {
        std::lock_guard lock(m_mutex);
        const auto found = m_faulted.find(kind);
        return found == m_faulted.end() ? 0 : found->second;
    }
    /// Waits until `count` requests have met `kind` or `timeout` passes; whether they had.
    bool waitForFaults(ProxyFault kind, int count, std::chrono::milliseconds timeout) {
        std::unique_lock lock(m_mutex);
        return m_changed.wait_for(lock, timeout, [&] { return m_faulted[kind] >= count; });
    }
    /// Faults from now on by `plan` (request counting goes on), holding bodies again.
    void setPlan(FaultPlan plan) {
        std::lock_guard lock(m_mutex);
        m_plan = std::move(plan);
        m_released = false;
        m_faultedPaths.clear();
        m_faultTurn = 0;
    }

    /// Lets every held body go on (and every later one through unheld).
    void release() {
        std::lock_guard lock(m_mutex);
        m_released = true;
        m_changed.notify_all();
    }

private:
    static sockaddr_in loopback(int port) {
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        address.sin_port = htons(static_cast<std::uint16_t>(port));
        return address;
    }

    static bool sendAll(int fd, const char* data, std::size_t size) {
        while (size > 0) {
            const ssize_t sent = ::send(fd, data, size, MSG_NOSIGNAL);
            if (sent <= 0) return false;
            data += sent;
            size -= static_cast<std::size_t>(sent);
        }
        return true;
    }
    static bool sendAll(int fd, const std::string& s) { return sendAll(fd, s.data(), s.size()); }

    // A request's head (through the blank line), read from `fd` with `buffer` holding what came
    // after an earlier head; empty at the end of the connection.
    static std::string readHead(int fd, std::string& buffer) {
        for (;;) {
            const std::size_t end = buffer.find("\r\n\r\n");
            if (end != std::string::npos) {
                std::string head = buffer.substr(0, end + 4);
                buffer.erase(0, end + 4);
                return head;
            }
            char chunk[4096];
            const ssize_t got = ::recv(fd, chunk, sizeof(chunk), 0);
            if (got <= 0) return {};
            buffer.append(chunk, static_cast<std::size_t>(got));
        }
    }

    static bool isHeader(const std::string& line, const char* name) {
        const std::size_t n = std::char_traits<char>::length(name);
        if (line.size() <= n || line[n] != ':') return false;
        for (std::size_t i = 0; i < n; ++i)
            if (std::tolower(static_cast<unsigned char>(line[i])) != name[i]) return false;
        return true;
    }

    // `head` without its hop-by-hop connection headers, with `extra` lines added.
    static std::string rewriteHead(const std::string& head, const std::string& extra) {
        std::string out;
        std::size_t at = 0;
        bool first = true;
        while (at < head.size()) {
            const std::size_t end = head.find("\r\n", at);
            const std::string line = head.substr(at, end - at);
            at = end + 2;
            if (line.empty()) break;
            if (!first && (isHeader(line, "connection") || isHeader(line, "keep-alive"))) continue;
            out += line + "\r\n";
            first = false;
        }
        return out + extra + "\r\n";
    }

    // The upstream server's whole answer to `head`, or empty when it cannot be had.
    std::string fetchUpstream(const std::string& head) const {
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        const sockaddr_in address = loopback(m_upstreamPort);
        std::string answer;
        if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0 &&
            sendAll(fd, rewriteHead(head, "Connection: close\r\n"))) {
            char chunk[65536];
            for (ssize_t got; (got = ::recv(fd, chunk, sizeof(chunk), 0)) > 0;)
                answer.append(chunk, static_cast<std::size_t>(got));
        }
        ::close(fd);
        return answer;
    }

    // Whether segment `segment` of request `request`'s exchange is lost (segment 0: the
    // request itself), by a hash of the two (SplitMix64's finaliser) against segmentLoss.
    bool lost(int request, std::size_t segment, double probability) const {
        if (probability <= 0.0) return false;
        std::uint64_t z = (std::uint64_t(request) << 32) ^ std::uint64_t(segment);
        z += 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        const bool lostIt = double(z >> 11) * 0x1.0p-53 < probability;
        if (lostIt) ++m_lostPackets;
        return lostIt;
    }

    // One client connection's congestion window (FaultPlan::initialWindow).
    struct Window {
        std::size_t segments = 0;  // 0: no window
        std::size_t threshold = std::numeric_limits<std::size_t>::max();
        std::chrono::steady_clock::time_point lastSent{};
    };

    // `data` in segments, a window at a time with a round trip between windows (when `window`
    // has one), each lost segment sent after a round trip (`roundTrip`), or after the
    // retransmission timeout (`timeout`) when fewer than three segments follow it.
    bool sendPaced(int fd, const char* data, std::size_t size, int request, std::size_t& segment,
                   double probability, std::chrono::milliseconds roundTrip,
                   std::chrono::milliseconds timeout, Window& window) {
        constexpr std::size_t kDuplicateAcks = 3;
        constexpr std::size_t kBytes = FaultPlan::kSegmentBytes;
        const std::size_t segments = (size + kBytes - 1) / kBytes;
        for (std::size_t k = 0; k < segments;) {
            const std::size_t round =
                window.segments == 0 ? segments - k : std::min(window.segments, segments - k);
            bool lostInRound = false;
            for (const std::size_t end = k + round; k < end; ++k) {
                const std::size_t following = segments - k - 1;
                if (lost(request, ++segment, probability)) {
                    lostInRound = true;
                    std::this_thread::sleep_for(following >= kDuplicateAcks ? roundTrip : timeout);
                }
                const std::size_t bytes = std::min(kBytes, size - k * kBytes);
                waitForTheLink(bytes);
                if (!sendAll(fd, data + k * kBytes, bytes)) return false;
            }
            if (window.segments == 0) continue;
            if (k < segments) std::this_thread::sleep_for(roundTrip);  // the window's acks
            if (lostInRound) {
                window.threshold = std::max<std::size_t>(window.segments / 2, 2);
                window.segments = window.threshold;
            } else {
                window.segments =
                    window.segments < window.threshold ? window.segments * 2 : window.segments + 1;
            }
        }
        window.lastSent = std::chrono::steady_clock::now();
        return true;
    }

    // Waits until the shared link has carried `bytes` more after what it carries now.
    void waitForTheLink(std::size_t bytes) {
        std::chrono::steady_clock::time_point sent;
        {
            std::lock_guard lock(m_mutex);
            if (m_plan.linkBytesPerSecond <= 0.0) return;
            const auto now = std::chrono::steady_clock::now();
            m_linkFreeAt = std::max(m_linkFreeAt, now) +
                           std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                               std::chrono::duration<double>(static_cast<double>(bytes) /
                                                             m_plan.linkBytesPerSecond));
            sent = m_linkFreeAt;
        }
        std::this_thread::sleep_until(sent);
    }

    // The fault of request `request` for `head`, and the latency before its answer.
    std::pair<ProxyFault, std::chrono::milliseconds> faultFor(int request,
                                                              const std::string& head) {
        std::lock_guard lock(m_mutex);
        if (m_plan.faultEvery <= 0 || m_plan.kinds.empty() || request % m_plan.faultEvery != 0)
            return {ProxyFault::None, m_plan.latency};
        // "GET /path HTTP/1.1": the path.
        const std::size_t from = head.find(' ') + 1, to = head.find(' ', from);
        if (m_plan.oncePerPath && !m_faultedPaths.insert(head.substr(from, to - from)).second)
            return {ProxyFault::None, m_plan.latency};
        return {m_plan.kinds[m_faultTurn++ % m_plan.kinds.size()], m_plan.latency};
    }

    void count(ProxyFault kind) {
        std::lock_guard lock(m_mutex);
        ++m_faulted[kind];
        m_changed.notify_all();
    }

    void acceptLoop() {
        while (!m_stopping) {
            const int client = ::accept(m_listener, nullptr, nullptr);
            if (client < 0) {
                if (m_stopping) return;
                continue;
            }
            std::lock_guard lock(m_mutex);
            if (m_stopping) {
                ::close(client);
                return;
            }
            m_clients.insert(client);
            m_connections.emplace_back([this, client] {
                serve(client);
                std::lock_guard done(m_mutex);
                m_clients.erase(client);
                ::close(client);
            });
        }
    }

    // A request being answered (maxInFlight), until leave().
    class InFlight {
    public:
        explicit InFlight(FaultProxy& proxy) : m_proxy(proxy) {
            const int now = ++m_proxy.m_inFlight;
            int seen = m_proxy.m_maxInFlight.load();
            while (now > seen && !m_proxy.m_maxInFlight.compare_exchange_weak(seen, now)) {
            }
        }
        void leave() {
            if (!m_left) --m_proxy.m_inFlight;
            m_left = true;
        }
        ~InFlight() { leave(); }
        InFlight(const InFlight&) = delete;
        InFlight& operator=(const InFlight&) = delete;

    private:
        FaultProxy& m_proxy;
        bool m_left = false;
    };

    // Answers the requests of one client connection until it closes or a fault closes it.
    void serve(int client) {
        std::string buffer;
        Window window;
        for (;;) {
            const std::string head = readHead(client, buffer);
            if (head.empty()) return;
            InFlight answering(*this);
            const int request = ++m_requests;
            const auto [fault, latency] = faultFor(request, head);
            double loss = 0.0;
            std::chrono::milliseconds retransmit{0};
            std::size_t initialWindow = 0;
            {
                std::lock_guard lock(m_mutex);
                loss = m_plan.segmentLoss;
                retransmit = m_plan.retransmitDelay;
                initialWindow = m_plan.initialWindow;
            }
            // A new connection, or one idle for longer than a retransmission timeout (a round
            // trip and the least timeout, as Linux's), starts with the initial window again.
            const bool idle =
                std::chrono::steady_clock::now() - window.lastSent > latency + retransmit;
            if (initialWindow > 0 && (window.segments == 0 || idle))
                window.segments = initialWindow;
            if (initialWindow == 0) window.segments = 0;
            std::size_t segment = 0;
            if (lost(request, segment, loss)) std::this_thread::sleep_for(retransmit);
            if (latency.count() > 0) std::this_thread::sleep_for(latency);
            answering.leave();
            if (fault == ProxyFault::Reset) {
                const linger reset{1, 0};  // close() sends RST
                ::setsockopt(client, SOL_SOCKET, SO_LINGER, &reset, sizeof(reset));
                count(fault);
                return;
            }
            if (fault == ProxyFault::Drop) {
                count(fault);
                return;
            }
            if (fault == ProxyFault::ServerError) {
                count(fault);
                if (!sendAll(client,
                             "HTTP/1.1 503 Service Unavailable\r\nContent-Length: 0\r\n\r\n"))
                    return;
                continue;
            }
            const std::string answer = fetchUpstream(head);  // after leave(): quick, local
            const std::size_t split = answer.find("\r\n\r\n");
            if (split == std::string::npos) {
                sendAll(client, "HTTP/1.1 502 Bad Gateway\r\nContent-Length: 0\r\n\r\n");
                continue;
            }
            const std::string headers = rewriteHead(answer.substr(0, split + 4), "");
            const std::string body = answer.substr(split + 4);
            if (fault == ProxyFault::None && (loss > 0.0 || window.segments > 0)) {
                const std::string whole = headers + body;
                if (!sendPaced(client, whole.data(), whole.size(), request, segment, loss, latency,
                               retransmit, window))
                    return;
                continue;
            }
            if (!sendAll(client, headers)) return;
            if (fault == ProxyFault::Truncated) {
                sendAll(client, body.data(), body.size() / 2);
                count(fault);
                return;
            }
            if (fault == ProxyFault::HoldBody) {
                sendAll(client, body.data(), body.size() / 2);
                count(fault);
                std::unique_lock lock(m_mutex);
                m_changed.wait(lock, [&] { return m_released || m_stopping.load(); });
                lock.unlock();
                if (!sendAll(client, body.data() + body.size() / 2, body.size() - body.size() / 2))
                    return;
                continue;
            }
            if (fault == ProxyFault::SlowBody) {
                const std::size_t piece = std::max<std::size_t>(1, (body.size() + 7) / 8);
                for (std::size_t at = 0; at < body.size(); at += piece) {
                    if (!sendAll(client, body.data() + at, std::min(piece, body.size() - at)))
                        return;
                    std::this_thread::sleep_for(std::chrono::milliseconds(25));
                }
                count(fault);
                continue;
            }
            if (!sendAll(client, body)) return;
        }
    }

    const int m_upstreamPort;
    FaultPlan m_plan;  // guarded by m_mutex
    std::chrono::steady_clock::time_point m_linkFreeAt{};  // guarded by m_mutex
    int m_listener = -1;
    int m_port = 0;
    std::atomic<bool> m_stopping{false};
    std::atomic<int> m_requests{0};
    mutable std::atomic<int> m_lostPackets{0};
    std::atomic<int> m_inFlight{0};
    std::atomic<int> m_maxInFlight{0};
    mutable std::mutex m_mutex;
    std::condition_variable m_changed;
    std::map<ProxyFault, int> m_faulted;
    std::set<int> m_clients;
    std::set<std::string> m_faultedPaths;
    std::size_t m_faultTurn = 0;  // faults made under the plan: the next kind's turn
    std::vector<std::thread> m_connections;
    bool m_released = false;
    std::thread m_acceptor;
};

}  // namespace terrain::test
