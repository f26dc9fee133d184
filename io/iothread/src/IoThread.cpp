// IoThread: one loop that pops the highest-priority request under the mutex, reads it with
// the mutex released, and files the outcome for poll().
#include "terrain/iothread/IoThread.h"

#include "terrain/base/Assert.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace terrain::io {

namespace {

/// The most records m_pool holds: recycle() and run() add one only below this.
std::size_t poolBound(const IoThreadOptions& options) { return options.maxUnpolled + 1; }

std::uint64_t recordBytes(const PatchRecord& r) {
    return static_cast<std::uint64_t>(r.heights.size() * sizeof(float) + r.valid.size() +
                                      r.blockErrors.size() * sizeof(BlockErrors) +
                                      sizeof(PatchInfo));
}

}  // namespace

Result<std::unique_ptr<IoThread>> IoThread::start(const std::filesystem::path& pyramidDir,
                                                  const IoThreadOptions& options) {
    TERRAIN_ASSERT(options.maxUnpolled >= 1, "IoThread: maxUnpolled must be at least 1");
    TERRAIN_ASSERT(options.faults.errorRate >= 0.0 && options.faults.errorRate <= 1.0,
                   "IoThread: errorRate outside [0, 1]");
    TERRAIN_ASSERT(options.faults.addedLatencyMs >= 0.0, "IoThread: negative addedLatencyMs");
    auto reader = PyramidReader::open(pyramidDir, options.maxOpenShards);
    if (!reader) return reader.error();
    return std::unique_ptr<IoThread>(new IoThread(std::move(reader).value(), options));
}

IoThread::IoThread(PyramidReader reader, const IoThreadOptions& options)
    : m_options(options), m_layout(reader.layout()), m_reader(std::move(reader)) {
    // Up front, so recycling never allocates, and neither do the completions of reads
    // (their count is capped; only cancels beyond the cap can grow m_ready).
    m_pool.reserve(poolBound(m_options));
    m_ready.reserve(m_options.maxUnpolled);
    // Started last: the thread sees every member constructed (thread start synchronises).
    m_thread = std::jthread([this](const std::stop_token& stop) { run(stop); });
}

IoThread::~IoThread() {
    // request_stop wakes m_wake through the stop token; the thread exits at its next wait.
    m_thread.request_stop();
    m_thread.join();
}

bool IoThread::submit(const PatchId& id, float priority) {
    TERRAIN_ASSERT(!std::isnan(priority), "IoThread::submit: NaN priority");
    {
        const std::lock_guard lock(m_mutex);
        if (m_inFlight && m_inFlight->id == id && !m_inFlight->cancelled) return false;
        if (!m_pending.request(id, priority)) return false;  // re-prioritised
        addRequestTimeLocked(id, Clock::now());
        ++m_stats.requested;
    }
    m_wake.notify_all();
    return true;
}

bool IoThread::reprioritise(const PatchId& id, float priority) {
    TERRAIN_ASSERT(!std::isnan(priority), "IoThread::reprioritise: NaN priority");
    const std::lock_guard lock(m_mutex);
    if (!m_pending.contains(id)) return false;
    m_pending.request(id, priority);  // re-prioritises in place: allocates nothing
    return true;
}

bool IoThread::cancel(const PatchId& id) {
    {
        const std::lock_guard lock(m_mutex);
        // A pending request wins over an in-flight one: after cancel + submit of the same id
        // the pending one is the newer request.
        if (m_pending.cancel(id)) {
            // No record, no error text: creating it allocates nothing.
            Completion c;
            c.id = id;
            c.status = CompletionStatus::Cancelled;
            c.requestTime = takeRequestTimeLocked(id);
            c.completeTime = Clock::now();
            ++m_stats.cancelled;
            m_ready.push_back(std::move(c));
            return true;
        }
        if (!m_inFlight || m_inFlight->id != id || m_inFlight->cancelled) return false;
        m_inFlight->cancelled = true;  // the I/O thread reports it when the read ends
    }
    m_wake.notify_all();  // cuts an injected latency short
    return true;
}

std::size_t IoThread::poll(std::vector<Completion>& out) {
    std::size_t count = 0;
    {
        const std::lock_guard lock(m_mutex);
        count = m_ready.size();
        for (Completion& c : m_ready) out.push_back(std::move(c));
        m_ready.clear();
    }
    if (count > 0) m_wake.notify_all();  // room for more results
    return count;
}

void IoThread::recycle(PatchRecord&& record) {
    const std::lock_guard lock(m_mutex);
    // Bounded: at most one buffer per result the cap allows, plus the one being read.
    if (m_pool.size() < poolBound(m_options)) m_pool.push_back(std::move(record));
}

bool IoThread::waitForCompletion(std::chrono::milliseconds timeout) {
    std::unique_lock lock(m_mutex);
    m_stateChanged.wait_for(lock, timeout,
                        [&] { return !m_ready.empty() || (m_pending.empty() && !m_inFlight); });
    return !m_ready.empty();
}

bool IoThread::waitForState(const std::function<bool(const IoThreadStats&)>& reached,
                            std::chrono::milliseconds timeout) {
    std::unique_lock lock(m_mutex);
    return m_stateChanged.wait_for(lock, timeout, [&] { return reached(statsLocked()); });
}

IoThreadStats IoThread::stats() const {
    const std::lock_guard lock(m_mutex);
    return statsLocked();
}

IoThreadStats IoThread::statsLocked() const {
    IoThreadStats s = m_stats;
    s.queueDepth = m_pending.size();
    s.inFlight = m_inFlight ? 1 : 0;
    s.unpolled = m_ready.size();
    return s;
}

void IoThread::finishLocked(Completion&& completion) {
    switch (completion.status) {
        case CompletionStatus::Completed:
            ++m_stats.completed;
            m_stats.bytesRead += recordBytes(completion.record);
            break;
        case CompletionStatus::Failed:
            ++m_stats.failed;
            break;
        case CompletionStatus::Cancelled:
            ++m_stats.cancelled;
            break;
    }
    m_ready.push_back(std::move(completion));
    m_stateChanged.notify_all();
}

void IoThread::addRequestTimeLocked(const PatchId& id, Clock::time_point time) {
    if (m_spareTimeNodes.empty()) {
        // A new high-water request count: the only time this map allocates or rehashes.
        m_requestTimes.emplace(id, time);
        const std::size_t nodeCount = m_requestTimes.size();  // nothing is parked now
        if (m_spareTimeNodes.capacity() < nodeCount)
            m_spareTimeNodes.reserve(std::max(nodeCount, 2 * m_spareTimeNodes.capacity()));
        return;
    }
    RequestTimes::node_type node = std::move(m_spareTimeNodes.back());
    m_spareTimeNodes.pop_back();
    node.key() = id;
    node.mapped() = time;
    m_requestTimes.insert(std::move(node));
}

IoThread::Clock::time_point IoThread::takeRequestTimeLocked(const PatchId& id) {
    RequestTimes::node_type node = m_requestTimes.extract(id);
    TERRAIN_ASSERT(!node.empty(), "IoThread: a pending request without its request time");
    const Clock::time_point time = node.mapped();
    m_spareTimeNodes.push_back(std::move(node));  // within capacity: see addRequestTimeLocked
    return time;
}

void IoThread::run(const std::stop_token& stop) {
    const auto latency = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double, std::milli>(m_options.faults.addedLatencyMs));
    std::unique_lock lock(m_mutex);
    while (true) {
        const bool ready = m_wake.wait(lock, stop, [&] {
            return !m_pending.empty() && m_ready.size() < m_options.maxUnpolled;
        });
        if (!ready) return;  // stop requested

        const auto request = m_pending.popHighest();
        m_inFlight = InFlight{request->id, takeRequestTimeLocked(request->id), false};
        m_stateChanged.notify_all();
        PatchRecord record;
        if (!m_pool.empty()) {
            record = std::move(m_pool.back());
            m_pool.pop_back();
        }

        if (latency.count() > 0) {
            // Waits with the mutex released; a cancel or stop ends the wait early.
            m_wake.wait_for(lock, stop, latency, [&] { return m_inFlight->cancelled; });
            if (stop.stop_requested()) return;
        }

        const PatchId id = m_inFlight->id;
        std::optional<Status> outcome;
        bool injected = false;
        if (!m_inFlight->cancelled) {
            injected = m_options.faults.failsRead(id);
            lock.unlock();
            outcome =
                injected
                    ? Status(Error{fmt::format("{}: injected fault reading patch L{} ({}, {})",
                                               m_reader.folder().string(), id.level, id.x, id.y)})
                    : m_reader.readPatch(id, record);
            lock.lock();
        }

        Completion c;
        c.id = id;
        c.requestTime = m_inFlight->requestTime;
        c.completeTime = Clock::now();
        if (m_inFlight->cancelled) {
            c.status = CompletionStatus::Cancelled;
        } else if (outcome->ok()) {
            c.status = CompletionStatus::Completed;
            c.record = std::move(record);
        } else {
            c.status = CompletionStatus::Failed;
            c.error = outcome->error().message;
            if (injected) ++m_stats.injectedFaults;
        }
        if (c.status != CompletionStatus::Completed && m_pool.size() < poolBound(m_options))
            m_pool.push_back(std::move(record));
        m_inFlight.reset();
        finishLocked(std::move(c));
    }
}

}  // namespace terrain::io
