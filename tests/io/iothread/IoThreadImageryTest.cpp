// IoThread serving imagery tiles (issue 47) through the same thread and request queue as the
// heights: tiles equal their source's and carry the mips the I/O thread made of them (the
// render thread only uploads them), absent tiles complete without texels, one priority
// order across heights and imagery, cancelling an imagery key leaves the heights of the same
// patch alone, failures name the tile, a layer that cannot be opened fails only its own
// requests, a source handing out the wrong size fails the tile, and recycled tile storage
// is read into; what a layer at a URL fetches is counted with the heights' fetches.
// Deterministic: waits are on the thread's events, never sleeps.
#include "terrain/iothread/IoThread.h"
#include "terrain/pyramid/ImageryMips.h"

#include "FakeImagerySource.h"
#include "TempFolder.h"
#include "TinyPyramid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

using namespace std::chrono_literals;
using test::FakeImageryRules;

constexpr std::chrono::milliseconds kHangTimeout = 120s;

[[nodiscard]] bool pollUntil(IoThread& io, std::vector<Completion>& out, std::size_t count) {
    io.poll(out);
    while (out.size() < count) {
        if (!io.waitForCompletion(kHangTimeout)) return false;
        io.poll(out);
    }
    return true;
}

bool contains(const std::string& text, const std::string& needle) {
    return text.find(needle) != std::string::npos;
}

class IoThreadImageryTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto manifest = test::writeTinyPyramid(m_dir.path(), {});
        ASSERT_TRUE(manifest.ok()) << manifest.error().message;
        ASSERT_TRUE(test::addImageryLayers(m_dir.path(), 2).ok());
    }

    std::unique_ptr<IoThread> start(const FakeImageryRules& rules, IoThreadOptions options = {},
                                    std::uint32_t failToOpen = 0) {
        options.openImagery = test::fakeImageryOpener(rules, failToOpen);
        // One reader thread: these tests look at the order of completions (reads end in
        // the order they start); IoThreadTest covers several.
        options.readerThreads = 1;
        auto io = IoThread::start(m_dir.path(), options);
        EXPECT_TRUE(io.ok()) << (io.ok() ? "" : io.error().message);
        return io.ok() ? std::move(io).value() : nullptr;
    }

    test::TempFolder m_dir;
};

TEST_F(IoThreadImageryTest, ReadsTilesOfEveryLayerAndAbsentOnes) {
    FakeImageryRules rules;
    rules.absent = [](int layer, const PatchId& id) { return layer == 1 && id.level == 2; };
    auto io = start(rules);
    ASSERT_TRUE(io);
    EXPECT_EQ(io->imageryLayerCount(), 2);
    EXPECT_TRUE(io->imageryOpenError(0).empty());
    const PatchId a{1, 1, 0};
    const PatchId b{2, 3, 1};  // finer than this pyramid's finest: imagery may be
    EXPECT_TRUE(io->submit(TileKey{a, 0}, 1.0f));
    EXPECT_TRUE(io->submit(TileKey{a, 1}, 1.0f));  // another layer: another request
    EXPECT_TRUE(io->submit(a, 1.0f));              // the heights: another one again
    EXPECT_TRUE(io->submit(TileKey{b, 1}, 1.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 4));
    ASSERT_EQ(done.size(), 4U);
    int heights = 0;
    for (const Completion& c : done) {
        ASSERT_EQ(c.status, CompletionStatus::Completed) << c.error;
        if (!c.key().isImagery()) {
            ++heights;
            EXPECT_EQ(c.record.id, a);
            EXPECT_TRUE(c.imagery.rgba.empty());
            continue;
        }
        EXPECT_TRUE(c.record.heights.empty());
        EXPECT_EQ(c.imagery.id, c.id);
        if (c.imageryLayer == 1 && c.id == b) {
            EXPECT_FALSE(c.imagery.info.present);
            EXPECT_TRUE(c.imagery.rgba.empty());
            EXPECT_TRUE(c.imagery.mips.empty());
            continue;
        }
        ASSERT_TRUE(c.imagery.info.present);
        ImageryTile expected;
        test::fillFakeImagery(c.imageryLayer, c.id, kImageryTileBytes, expected);
        EXPECT_EQ(c.imagery.rgba, expected.rgba);
        EXPECT_EQ(c.imagery.info, expected.info);
        // Mips 1 and 2, one after the other: the box filter's, made off the render thread.
        std::vector<std::uint8_t> mip1(imageryMipBytes(1));
        std::vector<std::uint8_t> mip2(imageryMipBytes(2));
        halveImagery(expected.rgba, kImageryTileTexels, mip1);
        halveImagery(mip1, kImageryTileTexels / 2, mip2);
        ASSERT_EQ(c.imagery.mips.size(), kImageryMipChainBytes);
        EXPECT_TRUE(std::equal(mip1.begin(), mip1.end(), c.imagery.mips.begin()));
        EXPECT_TRUE(std::equal(mip2.begin(), mip2.end(), c.imagery.mips.begin() + mip1.size()));
    }
    EXPECT_EQ(heights, 1);
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.requested, 4U);
    EXPECT_EQ(s.completed, 4U);
}

TEST_F(IoThreadImageryTest, WhatImageryCostsOverHttpIsCountedWithTheHeights) {
    FakeImageryRules rules;
    rules.overHttp = true;
    rules.fails = [](int layer, const PatchId& id) { return layer == 1 && id.level == 2; };
    auto io = start(rules);
    ASSERT_TRUE(io);
    // Opening each of the two layers fetched its index; the heights are in a folder.
    EXPECT_EQ(io->stats().http.requests, 2U);
    EXPECT_TRUE(io->submit(TileKey{{1, 1, 0}, 0}, 1.0f));
    EXPECT_TRUE(io->submit(TileKey{{1, 1, 0}, 1}, 1.0f));
    EXPECT_TRUE(io->submit(TileKey{{2, 3, 1}, 1}, 1.0f));  // fails, after its request
    EXPECT_TRUE(io->submit(PatchId{1, 1, 0}, 1.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 4));
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.failed, 1U);
    EXPECT_EQ(s.http.requests, 5U) << "two indexes, three tile files";
    EXPECT_EQ(s.http.fetched, 5U);
    EXPECT_EQ(s.http.fetchedBytes, 5U * test::kFakeImageryFileBytes);
}

TEST_F(IoThreadImageryTest, HeightsAndImageryShareOnePriorityOrder) {
    IoThreadOptions options;
    options.maxUnpolled = 2;
    auto io = start({}, options);
    ASSERT_TRUE(io);
    // Two finished results fill the cap; the thread then waits for poll().
    EXPECT_TRUE(io->submit(PatchId{0, 0, 0}, 0.0f));
    EXPECT_TRUE(io->submit(TileKey{{0, 0, 0}, 0}, 0.0f));
    ASSERT_TRUE(
        io->waitForState([](const IoThreadStats& s) { return s.unpolled == 2; }, kHangTimeout));
    const PatchId p{1, 1, 0};
    const std::vector<std::pair<TileKey, float>> requests = {
        {TileKey{p, 0}, 2.0f}, {p, 5.0f}, {TileKey{p, 1}, 4.0f}, {PatchId{1, 0, 0}, 3.0f}};
    for (const auto& [key, priority] : requests) EXPECT_TRUE(io->submit(key, priority));
    EXPECT_FALSE(io->submit(TileKey{p, 0}, 6.0f));  // re-prioritised, not a new request
    EXPECT_TRUE(io->reprioritise(TileKey{p, 1}, 1.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 6));
    ASSERT_EQ(done.size(), 6U);
    const std::vector<TileKey> order = {PatchId{0, 0, 0}, TileKey{{0, 0, 0}, 0}, TileKey{p, 0}, p,
                                        PatchId{1, 0, 0}, TileKey{p, 1}};
    for (std::size_t i = 0; i < order.size(); ++i) {
        EXPECT_EQ(done[i].key(), order[i]) << "completion " << i;
        EXPECT_EQ(done[i].status, CompletionStatus::Completed) << done[i].error;
    }
}

TEST_F(IoThreadImageryTest, CancellingAnImageryKeyLeavesTheHeightsOfItsPatch) {
    IoThreadOptions options;
    options.maxUnpolled = 1;
    auto io = start({}, options);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->submit(PatchId{0, 0, 0}, 9.0f));
    ASSERT_TRUE(
        io->waitForState([](const IoThreadStats& s) { return s.unpolled == 1; }, kHangTimeout));
    const PatchId p{1, 1, 0};
    EXPECT_TRUE(io->submit(p, 1.0f));
    EXPECT_TRUE(io->submit(TileKey{p, 0}, 1.0f));
    EXPECT_TRUE(io->cancel(TileKey{p, 0}));
    EXPECT_FALSE(io->cancel(TileKey{p, 0}));
    EXPECT_FALSE(io->cancel(TileKey{p, 1}));  // never requested
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 3));
    ASSERT_EQ(done.size(), 3U);
    EXPECT_EQ(done[1].key(), (TileKey{p, 0}));
    EXPECT_EQ(done[1].status, CompletionStatus::Cancelled);
    EXPECT_TRUE(done[1].imagery.rgba.empty());
    EXPECT_EQ(done[2].key(), TileKey{p});
    EXPECT_EQ(done[2].status, CompletionStatus::Completed) << done[2].error;
    EXPECT_EQ(io->stats().cancelled, 1U);
}

TEST_F(IoThreadImageryTest, CancelDuringAnImageryReadIsReportedAsCancelled) {
    IoThreadOptions options;
    options.faults.addedLatencyMs = 24.0 * 3600.0 * 1000.0;  // the read waits until cancelled
    auto io = start({}, options);
    ASSERT_TRUE(io);
    const TileKey key{{1, 0, 0}, 1};
    EXPECT_TRUE(io->submit(key, 1.0f));
    ASSERT_TRUE(
        io->waitForState([](const IoThreadStats& s) { return s.inFlight == 1; }, kHangTimeout));
    EXPECT_FALSE(io->submit(key, 3.0f));  // being read
    EXPECT_TRUE(io->cancel(key));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 1));
    EXPECT_EQ(done[0].key(), key);
    EXPECT_EQ(done[0].status, CompletionStatus::Cancelled);
}

TEST_F(IoThreadImageryTest, FailuresNameTheTileAndAnUnopenedLayerFailsOnlyItself) {
    FakeImageryRules rules;
    rules.fails = [](int layer, const PatchId& id) { return layer == 0 && id == PatchId{1, 1, 0}; };
    auto io = start(rules, {}, /*failToOpen=*/0b10);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->imageryOpenError(0).empty());
    EXPECT_TRUE(contains(std::string(io->imageryOpenError(1)), "\"layer1\": cannot be opened"))
        << io->imageryOpenError(1);
    EXPECT_TRUE(io->submit(TileKey{{1, 1, 0}, 0}, 4.0f));
    EXPECT_TRUE(io->submit(TileKey{{1, 0, 0}, 1}, 3.0f));
    EXPECT_TRUE(io->submit(TileKey{{1, 0, 0}, 0}, 2.0f));
    EXPECT_TRUE(io->submit(PatchId{1, 0, 0}, 1.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 4));
    ASSERT_EQ(done.size(), 4U);
    EXPECT_EQ(done[0].status, CompletionStatus::Failed);
    EXPECT_TRUE(contains(done[0].error, "cannot read tile L1 (1, 0)")) << done[0].error;
    EXPECT_EQ(done[1].status, CompletionStatus::Failed);
    EXPECT_TRUE(contains(done[1].error, "\"layer1\": cannot be opened")) << done[1].error;
    EXPECT_EQ(done[2].status, CompletionStatus::Completed) << done[2].error;
    EXPECT_EQ(done[3].status, CompletionStatus::Completed) << done[3].error;
    const IoThreadStats s = io->stats();
    EXPECT_EQ(s.failed, 2U);
    EXPECT_EQ(s.injectedFaults, 0U);
}

TEST_F(IoThreadImageryTest, ATileOfTheWrongSizeFailsNamingIt) {
    FakeImageryRules rules;
    rules.texelBytes = kImageryTileBytes / 2;
    auto io = start(rules);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->submit(TileKey{{1, 1, 0}, 1}, 1.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 1));
    EXPECT_EQ(done[0].status, CompletionStatus::Failed);
    EXPECT_TRUE(contains(done[0].error, "\"layer1\": tile L1 (1, 0) has 131072 bytes"))
        << done[0].error;
}

TEST_F(IoThreadImageryTest, RecycledTileStorageIsReadInto) {
    IoThreadOptions options;
    options.maxUnpolled = 1;
    auto io = start({}, options);
    ASSERT_TRUE(io);
    EXPECT_TRUE(io->submit(TileKey{{0, 0, 0}, 0}, 0.0f));
    std::vector<Completion> done;
    ASSERT_TRUE(pollUntil(*io, done, 1));
    ASSERT_EQ(done[0].status, CompletionStatus::Completed);
    const std::uint8_t* storage = done[0].imagery.rgba.data();
    io->recycle(std::move(done[0].imagery));
    done.clear();
    EXPECT_TRUE(io->submit(TileKey{{1, 1, 1}, 1}, 0.0f));
    ASSERT_TRUE(pollUntil(*io, done, 1));
    ASSERT_EQ(done[0].status, CompletionStatus::Completed);
    EXPECT_EQ(done[0].imagery.rgba.data(), storage);
}

}  // namespace
}  // namespace terrain::io
