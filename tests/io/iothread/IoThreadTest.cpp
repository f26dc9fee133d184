// IoThread: patches read in the background equal PyramidReader's; priority order, the cap
// on unpolled results, cancelling, every request ending exactly once under a random storm,
// injected faults, a missing shard, buffer reuse, no allocation on the owner thread once
// warm, and shutdown cutting a read short; with several reader threads, reads at once, the
// same records, and every request (cancelled or not) ending once. Tests that look at the
// order of completions or at one read in flight use one reader thread. Deterministic: the tests
// wait on the thread's events (waitForState, waitForCompletion), never sleep, and assert no
// durations.
#include "terrain/iothread/IoThread.h"
#include "terrain/pyramid/PyramidReader.h"

#include "AllocationCounter.h"
#include "TempFolder.h"
#include "TinyPyramid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace terrain::io {
namespace {

using TempDir = terrain::test::TempFolder;
using namespace std::chrono_literals;

// Every wait is on an event of the thread; this bound only turns a hung thread into a
// failure instead of a test that never ends.
constexpr std::chrono::milliseconds kHangTimeout = 120s;

bool contains(const std::string& text, const std::string& needle) {
    return text.find(needle) != std::string::npos;
}

/// Waits until the thread's counters reach a state; false only when the thread hangs.
[[nodiscard]] bool waitForState(IoThread& io,
                                const std::function<bool(const IoThreadStats&)>& reached) {
    return io.waitForState(reached, kHangTimeout);
}

/// Polls until `out` holds at least `count` completions, waiting on each outcome: every
/// pass takes at least one completion, so it ends within `count` passes.
[[nodiscard]] bool pollUntil(IoThread& io, std::vector<Completion>& out, std::size_t count) {
    io.poll(out);
    while (out.size() < count) {
        if (!io.waitForCompletion(kHangTimeout)) return false;  // hung, or nothing to come
        io.poll(out);
    }
    return true;
}

std::string patchName(const PatchId& id) {
    return "patch L" + std::to_string(id.level) + " (" + std::to_string(id.x) + ", " +
           std::to_string(id.y) + ")";
}

class IoThreadTest : public ::testing::Test {
protected:
    void SetUp() override {
        terrain::test::TinyPyramidOptions options;
        options.withNoData = true;
        auto manifest = terrain::test::writeTinyPyramid(m_dir.path(), options);
        ASSERT_TRUE(manifest.ok()) << manifest.error().message;
        auto layout = PyramidLayout::create(options.width, options.height, options.patchSamples,
                                            options.blockQuads, options.shardPatches);
        ASSERT_TRUE(layout.ok());
        for (int l = 0; l < layout.value().levelCount(); ++l)
            for (std::int64_t y = 0; y < layout.value().patchesY(l); ++y)
                for (std::int64_t x = 0; x < layout.value().patchesX(l); ++x)
                    m_patches.push_back(PatchId{l, x, y});
    }

    std::unique_ptr<IoThread> start(const IoThreadOptions& options = {}) {
        auto io = IoThread::start(m_dir.path(), options);
        EXPECT_TRUE(io.ok()) << (io.ok() ? "" : io.error().message);
        return io.ok() ? std::move(io).value() : nullptr;
    }

    TempDir m_dir;
    std::vector<PatchId> m_patches;  // every patch of every level, coarse to fine
};

/// Every patch submitted to `io`, polled, equal to a PyramidReader's byte for byte.
void expectReadsEqualToPyramidReader(IoThread& io, const std::filesystem::path& pyramid,
                                     const std::vector<PatchId>& patches) {
    ASSERT_GE(patches.size(), 10U);
    for (std::size_t i = 0; i < patches.size(); ++i)
        EXPECT_TRUE(io.submit(patches[i], static_cast<float>(i % 5)));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(io, done, patches.size()));
    ASSERT_EQ(done.size(), patches.size());

    auto reader = PyramidReader::open(pyramid);
    ASSERT_TRUE(reader.ok());
    std::uint64_t bytes = 0;
    std::map<std::tuple<int, std::int64_t, std::int64_t>, int> ended;
    for (const Completion& c : done) {
        ASSERT_EQ(c.status, CompletionStatus::Completed) << c.error;
        const int times = ++ended[{c.id.level, c.id.x, c.id.y}];
        EXPECT_EQ(times, 1) << "ended twice: " << patchName(c.id);
        EXPECT_LE(c.requestTime, c.completeTime);
        auto expected = reader.value().readPatch(c.id);
        ASSERT_TRUE(expected.ok()) << expected.error().message;
        EXPECT_EQ(c.record.id, c.id);
        EXPECT_EQ(c.record.info, expected.value().info);
        EXPECT_EQ(c.record.heights, expected.value().heights);
        EXPECT_EQ(c.record.valid, expected.value().valid);
        EXPECT_FALSE(c.record.valid.empty());
        ASSERT_EQ(c.record.blockErrors.size(), expected.value().blockErrors.size());
        for (std::size_t b = 0; b < c.record.blockErrors.size(); ++b)
            EXPECT_EQ(c.record.blockErrors[b], expected.value().blockErrors[b]);
        bytes += c.record.heights.size() * sizeof(float);
    }
    const IoThreadStats s = io.stats();
    EXPECT_EQ(s.requested, patches.size());
    EXPECT_EQ(s.completed, patches.size());
    EXPECT_EQ(s.failed + s.cancelled + s.queueDepth + s.inFlight + s.unpolled, 0U);
    EXPECT_GE(s.bytesRead, bytes);
}

TEST_F(IoThreadTest, SeveralReaderThreadsReadEveryPatchOnceEqualToPyramidReader) {
    IoThreadOptions options;
    options.readerThreads = 3;
    auto io = start(options);
    ASSERT_TRUE(io);
    EXPECT_EQ(io->readerThreads(), 3);
    // Shuffled: a child's heights may be predicted from a parent another thread (with its
    // own parent cache) read, or that none has read yet.
    std::vector<PatchId> patches = m_patches;
    std::shuffle(patches.begin(), patches.end(), std::mt19937(3));
    expectReadsEqualToPyramidReader(*io, m_dir.path(), patches);
}

TEST_F(IoThreadTest, SeveralReaderThreadsReadAtOnceAndCancelEach) {
    IoThreadOptions options;
    options.readerThreads = 3;
    options.faults.addedLatencyMs = 24.0 * 3600.0 * 1000.0;  // each read waits until cancelled
    auto io = start(options);
    ASSERT_TRUE(io);
    for (std::size_t i = 0; i < 5; ++i) EXPECT_TRUE(io->submit(m_patches[i], 0.0f));
    // Three reads at once: only reached when three threads read (one would stay at 1).
    ASSERT_TRUE(waitForState(
        *io, [](const IoThreadStats& s) { return s.inFlight == 3 && s.queueDepth == 2; }));
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_FALSE(io->submit(m_patches[i], 1.0f)) << "live: not a new request";
        EXPECT_TRUE(io->cancel(m_patches[i]));
        EXPECT_FALSE(io->cancel(m_patches[i])) << "cancelled once";
    }
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 5));
    ASSERT_EQ(done.size(), 5U);
    std::map<std::tuple<int, std::int64_t, std::int64_t>, int> ended;
    for (const Completion& c : done) {
        EXPECT_EQ(c.status, CompletionStatus::Cancelled);
        ++ended[{c.id.level, c.id.x, c.id.y}];
    }
    for (std::size_t i = 0; i < 5; ++i)
        EXPECT_EQ((ended[{m_patches[i].level, m_patches[i].x, m_patches[i].y}]), 1);
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.requested, 5U);
    EXPECT_EQ(s.cancelled, 5U);
    EXPECT_EQ(s.completed + s.failed + s.queueDepth + s.inFlight + s.unpolled, 0U);
    // The reads still pending when it goes are cut short: the destructor returns.
    for (std::size_t i = 5; i < 9; ++i) EXPECT_TRUE(io->submit(m_patches[i], 0.0f));
    ASSERT_TRUE(waitForState(*io, [](const IoThreadStats& t) { return t.inFlight == 3; }));
    io.reset();
}

TEST_F(IoThreadTest, ReadsPatchesEqualToPyramidReader) {
    IoThreadOptions options;
    options.readerThreads = 1;
    auto io = start(options);
    ASSERT_TRUE(io);
    expectReadsEqualToPyramidReader(*io, m_dir.path(), m_patches);
}

TEST_F(IoThreadTest, ServesHighestPriorityFirstAndCapsUnpolledResults) {
    IoThreadOptions options;
    options.readerThreads = 1;  // one thread ends reads in the order it starts them
    options.maxUnpolled = 2;
    auto io = start(options);
    ASSERT_TRUE(io);
    // Two finished results fill the cap; the thread then waits for poll().
    EXPECT_TRUE(io->submit(m_patches[0], 0.0f));
    EXPECT_TRUE(io->submit(m_patches[1], 0.0f));
    ASSERT_TRUE(waitForState(*io, [](const IoThreadStats& s) { return s.unpolled == 2; }));
    const std::vector<float> priorities = {1.0f, 7.0f, 3.0f, 7.0f, 5.0f, -1.0f};
    for (std::size_t i = 0; i < priorities.size(); ++i)
        EXPECT_TRUE(io->submit(m_patches[2 + i], priorities[i]));
    EXPECT_FALSE(io->submit(m_patches[7], 6.0f));       // re-prioritised: -1 → 6
    EXPECT_TRUE(io->reprioritise(m_patches[2], 2.0f));  // 1 → 2: still after 3
    EXPECT_FALSE(io->reprioritise(m_patches[0], 9.0f)) << "finished: not pending";
    EXPECT_FALSE(io->reprioritise(m_patches[8], 9.0f)) << "never requested";
    IoThreadStats s = io->stats();
    EXPECT_EQ(s.queueDepth, priorities.size());
    EXPECT_EQ(s.inFlight, 0U);
    EXPECT_EQ(s.unpolled, 2U);

    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 2 + priorities.size()));
    ASSERT_EQ(done.size(), 2 + priorities.size());
    // 7 (first arrival), 7, 6 (re-prioritised), 5, 3, 1.
    const std::vector<std::size_t> order = {0, 1, 3, 5, 7, 6, 4, 2};
    for (std::size_t i = 0; i < order.size(); ++i) {
        EXPECT_EQ(done[i].id, m_patches[order[i]]) << "completion " << i;
        EXPECT_EQ(done[i].status, CompletionStatus::Completed);
    }
}

TEST_F(IoThreadTest, CancelOfPendingRequestYieldsCancelledCompletion) {
    IoThreadOptions options;
    options.maxUnpolled = 1;
    auto io = start(options);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->submit(m_patches[0], 1.0f));
    ASSERT_TRUE(waitForState(*io, [](const IoThreadStats& s) { return s.unpolled == 1; }));
    EXPECT_TRUE(io->submit(m_patches[1], 1.0f));
    EXPECT_TRUE(io->cancel(m_patches[1]));
    EXPECT_FALSE(io->cancel(m_patches[1]));  // already ended
    EXPECT_FALSE(io->cancel(m_patches[0]));  // finished, not cancellable
    EXPECT_FALSE(io->cancel(m_patches[2]));  // never requested

    std::vector<Completion> done;
    EXPECT_EQ(io->poll(done), 2U);
    ASSERT_EQ(done.size(), 2U);
    EXPECT_EQ(done[0].id, m_patches[0]);
    EXPECT_EQ(done[0].status, CompletionStatus::Completed);
    EXPECT_EQ(done[1].id, m_patches[1]);
    EXPECT_EQ(done[1].status, CompletionStatus::Cancelled);
    EXPECT_TRUE(done[1].record.heights.empty());
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.requested, 2U);
    EXPECT_EQ(s.completed, 1U);
    EXPECT_EQ(s.cancelled, 1U);
    EXPECT_EQ(s.queueDepth, 0U);
}

TEST_F(IoThreadTest, CancelDuringReadIsReportedAsCancelled) {
    IoThreadOptions options;
    options.faults.addedLatencyMs = 24.0 * 3600.0 * 1000.0;  // the read waits until cancelled
    auto io = start(options);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->submit(m_patches[3], 1.0f));
    ASSERT_TRUE(waitForState(*io, [](const IoThreadStats& s) { return s.inFlight == 1; }));
    EXPECT_FALSE(io->submit(m_patches[3], 9.0f));  // being read: not a new request
    EXPECT_TRUE(io->cancel(m_patches[3]));
    EXPECT_FALSE(io->cancel(m_patches[3]));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 1));
    ASSERT_EQ(done.size(), 1U);
    EXPECT_EQ(done[0].id, m_patches[3]);
    EXPECT_EQ(done[0].status, CompletionStatus::Cancelled);
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.requested, 1U);
    EXPECT_EQ(s.cancelled, 1U);
    EXPECT_EQ(s.completed + s.failed, 0U);
}

class IoThreadStormTest : public IoThreadTest, public ::testing::WithParamInterface<int> {};

TEST_P(IoThreadStormTest, EveryRequestEndsExactlyOnceUnderRandomStorm) {
    IoThreadOptions options;
    options.readerThreads = GetParam();
    options.maxUnpolled = 3;
    options.faults = {0.3, 0.0, 7};
    auto io = start(options);
    ASSERT_TRUE(io);
    std::mt19937 rng(99);
    std::map<std::tuple<int, std::int64_t, std::int64_t>, int> live;  // requests not ended
    std::uint64_t created = 0;
    std::vector<Completion> done;
    const auto account = [&] {
        for (const Completion& c : done) {
            int& n = live[{c.id.level, c.id.x, c.id.y}];
            EXPECT_GT(n, 0) << "a completion without a live request: " << patchName(c.id);
            --n;
            if (c.status == CompletionStatus::Completed) io->recycle(PatchRecord(c.record));
        }
        done.clear();
    };
    for (int step = 0; step < 4000; ++step) {
        const PatchId& id = m_patches[rng() % m_patches.size()];
        const auto op = rng() % 10;
        if (op < 6) {
            if (io->submit(id, static_cast<float>(rng() % 4))) {
                ++created;
                ++live[{id.level, id.x, id.y}];
            }
        } else if (op < 9) {
            io->cancel(id);
        } else {
            io->poll(done);
            account();
        }
    }
    // Drain: each pass takes every outcome so far, then waits for the next one (or for
    // the thread to run out of work), so the loop ends within one pass per request.
    while (true) {
        io->poll(done);
        account();
        const IoThreadStats s = io->stats();
        if (s.queueDepth + s.inFlight + s.unpolled == 0) break;
        ASSERT_TRUE(waitForState(*io, [](const IoThreadStats& t) {
            return t.unpolled > 0 || t.queueDepth + t.inFlight == 0;
        }));
    }
    for (const auto& [id, n] : live) EXPECT_EQ(n, 0);
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.requested, created);
    EXPECT_EQ(s.completed + s.failed + s.cancelled, created);
    EXPECT_GT(s.cancelled, 0U);
    EXPECT_GT(s.failed, 0U);
    EXPECT_EQ(s.failed, s.injectedFaults);
}

INSTANTIATE_TEST_SUITE_P(ReaderThreads, IoThreadStormTest, ::testing::Values(1, 3));

TEST_F(IoThreadTest, InjectedFaultsAreCountedAndNameThePatch) {
    IoThreadOptions options;
    options.faults = {0.3, 0.0, 42};
    auto io = start(options);
    ASSERT_TRUE(io);
    std::size_t expectedFaults = 0;
    for (const PatchId& id : m_patches) {
        EXPECT_TRUE(io->submit(id, 0.0f));
        if (options.faults.failsRead(id)) ++expectedFaults;
    }
    ASSERT_GT(expectedFaults, 0U);
    ASSERT_LT(expectedFaults, m_patches.size());
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, m_patches.size()));
    ASSERT_EQ(done.size(), m_patches.size());
    for (const Completion& c : done) {
        if (options.faults.failsRead(c.id)) {
            EXPECT_EQ(c.status, CompletionStatus::Failed);
            EXPECT_TRUE(contains(c.error, "injected fault")) << c.error;
            EXPECT_TRUE(contains(c.error, patchName(c.id))) << c.error;
        } else {
            EXPECT_EQ(c.status, CompletionStatus::Completed) << c.error;
        }
    }
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.failed, expectedFaults);
    EXPECT_EQ(s.injectedFaults, expectedFaults);
    EXPECT_EQ(s.completed, m_patches.size() - expectedFaults);

    // The same seed fails the same patches; another seed fails others.
    const FaultInjection other{0.3, 0.0, 43};
    std::size_t differ = 0;
    for (const PatchId& id : m_patches)
        if (other.failsRead(id) != options.faults.failsRead(id)) ++differ;
    EXPECT_GT(differ, 0U);
}

TEST_F(IoThreadTest, MissingShardFileGivesFailureNamingTheFile) {
    auto layout = PyramidLayout::create(37, 29, 9, 4, 2);
    ASSERT_TRUE(layout.ok());
    const PatchId victim = m_patches.back();
    const std::filesystem::path shard =
        m_dir.path() / layout.value().shardPath(layout.value().shardOf(victim));
    ASSERT_TRUE(std::filesystem::remove(shard)) << shard;
    IoThreadOptions options;
    options.readerThreads = 1;  // completions in priority order
    auto io = start(options);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->submit(victim, 1.0f));
    EXPECT_TRUE(io->submit(m_patches.front(), 0.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 2));
    ASSERT_EQ(done.size(), 2U);
    EXPECT_EQ(done[0].id, victim);
    EXPECT_EQ(done[0].status, CompletionStatus::Failed);
    EXPECT_TRUE(contains(done[0].error, shard.filename().string())) << done[0].error;
    EXPECT_TRUE(contains(done[0].error, patchName(victim))) << done[0].error;
    EXPECT_EQ(done[1].status, CompletionStatus::Completed) << done[1].error;
    EXPECT_EQ(io->stats().failed, 1U);
}

TEST_F(IoThreadTest, RecycledRecordStorageIsReadInto) {
    IoThreadOptions options;
    options.maxUnpolled = 1;
    auto io = start(options);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->submit(m_patches[0], 0.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 1));
    ASSERT_EQ(done[0].status, CompletionStatus::Completed);
    const float* storage = done[0].record.heights.data();
    io->recycle(std::move(done[0].record));
    done.clear();
    EXPECT_TRUE(io->submit(m_patches[1], 0.0f));
    ASSERT_TRUE(pollUntil(*io, done, 1));
    ASSERT_EQ(done[0].status, CompletionStatus::Completed);
    EXPECT_EQ(done[0].id, m_patches[1]);
    EXPECT_EQ(done[0].record.heights.data(), storage);
}

TEST_F(IoThreadTest, OwnerThreadAllocatesNothingOnceWarm) {
    // Only the owner thread is counted: the I/O thread may allocate while it reads.
    constexpr std::size_t kBatch = 8;  // requests a frame submits; 12 at most with re-submits
    IoThreadOptions options;
    options.maxUnpolled = 2 * kBatch;  // room for a whole frame: the thread never waits in one
    auto io = start(options);
    ASSERT_TRUE(io);
    ASSERT_GE(m_patches.size(), options.maxUnpolled + kBatch);
    std::vector<Completion> out;
    out.reserve(options.maxUnpolled + kBatch);  // the caller's one vector, cleared every frame

    // A cancel-heavy frame: submit a batch of patches, submit some again (re-prioritised, or
    // a new request when the first one has already finished), cancel most, then (without
    // polling) wait until every request of the frame has ended, poll once and recycle. No
    // gtest assertion inside: it could allocate. False on a timeout or a lost request.
    std::mt19937 rng(5);
    std::uint64_t created = 0;
    const auto frame = [&]() -> bool {
        const std::size_t first = rng() % (m_patches.size() - kBatch + 1);
        std::size_t requests = 0;
        for (std::size_t i = 0; i < kBatch; ++i)
            if (io->submit(m_patches[first + i], static_cast<float>(rng() % 4))) ++requests;
        for (std::size_t i = 0; i < kBatch / 2; ++i)
            if (io->submit(m_patches[first + rng() % kBatch], static_cast<float>(rng() % 4)))
                ++requests;
        for (std::size_t i = 0; i < kBatch; ++i)
            if (rng() % 4 != 0) io->cancel(m_patches[first + i]);
        created += requests;
        // The cap is never reached in a frame, so the thread ends every request on its own.
        if (!io->waitForState([requests](const IoThreadStats& s) { return s.unpolled >= requests; },
                              kHangTimeout))
            return false;
        if (io->poll(out) != requests) return false;
        for (Completion& c : out)
            if (c.status == CompletionStatus::Completed) io->recycle(std::move(c.record));
        out.clear();
        return true;
    };

    {
        const terrain::test::AllocationScope warmUp;
        // The high-water marks, reached deterministically: finished results fill the cap,
        // so the thread waits while kBatch more requests (a frame's most at once) are all
        // pending; cancelling those fills the completion list beyond any frame's.
        const std::size_t cap = options.maxUnpolled;
        for (std::size_t i = 0; i < cap; ++i) EXPECT_TRUE(io->submit(m_patches[i], 0.0f));
        ASSERT_TRUE(waitForState(*io, [cap](const IoThreadStats& s) { return s.unpolled == cap; }));
        for (std::size_t i = cap; i < cap + kBatch; ++i)
            EXPECT_TRUE(io->submit(m_patches[i], 0.0f));
        EXPECT_EQ(io->stats().queueDepth, kBatch);
        for (std::size_t i = cap; i < cap + kBatch; ++i) EXPECT_TRUE(io->cancel(m_patches[i]));
        EXPECT_EQ(io->poll(out), cap + kBatch);
        for (Completion& c : out)
            if (c.status == CompletionStatus::Completed) io->recycle(std::move(c.record));
        out.clear();
        for (int i = 0; i < 20; ++i) ASSERT_TRUE(frame()) << "warm-up frame " << i;
        EXPECT_GT(warmUp.allocations(), 0u) << "the counter must see the first requests";
    }

    const IoThreadStats before = io->stats();
    const std::uint64_t createdBefore = created;
    int framesDone = 0;
    std::uint64_t allocations = 0;
    {
        const terrain::test::AllocationScope scope;
        while (framesDone < 50 && frame()) ++framesDone;
        allocations = scope.allocations();
    }
    EXPECT_EQ(framesDone, 50) << "a frame timed out or lost a request";
    EXPECT_EQ(allocations, 0u);
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.requested - before.requested, created - createdBefore);
    EXPECT_EQ(s.completed + s.failed + s.cancelled, s.requested);
    EXPECT_GT(s.cancelled - before.cancelled, 0U);
    EXPECT_GT(s.completed - before.completed, 0U);
    EXPECT_EQ(s.failed, 0U);
}

TEST_F(IoThreadTest, DestructorCutsAReadShortAndDropsPendingWork) {
    IoThreadOptions options;
    options.readerThreads = 1;  // one read in flight, the rest pending
    // Every read would take a day: the destructor returns only because it cuts the read
    // short (when it does not, the test hangs until ctest's timeout names it).
    options.faults.addedLatencyMs = 24.0 * 3600.0 * 1000.0;
    auto io = start(options);
    ASSERT_TRUE(io);
    for (const PatchId& id : m_patches) EXPECT_TRUE(io->submit(id, 0.0f));
    ASSERT_TRUE(waitForState(*io, [](const IoThreadStats& s) { return s.inFlight == 1; }));
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.queueDepth, m_patches.size() - 1);
    EXPECT_EQ(s.completed + s.failed + s.cancelled, 0U);
    io.reset();
}

TEST(IoThreadStartTest, MissingPyramidIsAnError) {
    auto io = IoThread::start("/nonexistent/terrain-pyramid");
    ASSERT_FALSE(io.ok());
    EXPECT_TRUE(contains(io.error().message, "/nonexistent/terrain-pyramid")) << io.error().message;
}

}  // namespace
}  // namespace terrain::io
