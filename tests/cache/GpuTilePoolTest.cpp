// cache::GpuTilePool on a real context: capacity from the budget, layer bookkeeping,
// uploads through the pixel-buffer ring that round-trip exactly, the per-frame budget and
// ring wrap-around over many frames.
#include "GlTestFixture.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Buffer.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <vector>

namespace terrain::test {
namespace {

class GpuTilePoolTest : public GlTest {
protected:
    // N = 17 → 19 × 19 heights with apron, 4 × 4 blocks of 4 quads.
    static io::PyramidLayout layout() { return io::PyramidLayout::create(257, 257, 17, 4).value(); }

    static cache::GpuTilePool makePool(int layers, std::size_t uploadBudget,
                                       std::size_t ringBytes = 0) {
        auto created = cache::GpuTilePool::create(
            layout(), {.budgetBytes = cache::GpuTilePool::bytesPerLayer(layout()) *
                                      static_cast<std::size_t>(layers),
                       .uploadBudgetBytesPerFrame = uploadBudget,
                       .ringBytes = ringBytes});
        EXPECT_TRUE(created) << (created ? "" : created.error().message);
        return std::move(created).value();
    }

    /// Heights and errors distinct per patch and per sample, so misplaced data shows.
    static io::PatchRecord makeRecord(const io::PatchId& id, int salt = 0) {
        const io::PyramidLayout l = layout();
        io::PatchRecord record;
        record.id = id;
        const int t = l.tileSamples();
        const float base = static_cast<float>(id.x * 1000 + id.y * 100000 + salt * 7);
        for (int i = 0; i < t * t; ++i) {
            record.heights.push_back(base + static_cast<float>(i) * 0.25f - 3.5f);
        }
        record.info.minHeight = record.heights.front();
        record.info.maxHeight = record.heights.back();
        const int b = l.blocksPerSide();
        for (int i = 0; i < b * b; ++i) {
            const float e = base * 0.5f + static_cast<float>(i);
            record.blockErrors.push_back({e, e + 0.125f, e + 0.5f, e + 2.0f});
        }
        return record;
    }

    static void expectLayerHolds(const cache::GpuTilePool& pool, int layer,
                                 const io::PatchRecord& record) {
        const io::PyramidLayout l = layout();
        const int t = l.tileSamples();
        const int b = l.blocksPerSide();
        std::vector<float> heights(static_cast<std::size_t>(t * t));
        pool.heights().readBack({.layer = layer, .width = t, .height = t}, GL_RED, GL_FLOAT,
                                std::as_writable_bytes(std::span(heights)));
        EXPECT_EQ(heights, record.heights) << "heights of layer " << layer;
        std::vector<io::BlockErrors> errors(static_cast<std::size_t>(b * b));
        pool.blockErrors().readBack({.layer = layer, .width = b, .height = b}, GL_RGBA, GL_FLOAT,
                                    std::as_writable_bytes(std::span(errors)));
        EXPECT_EQ(errors, record.blockErrors) << "block errors of layer " << layer;
        // Each block's own heights, worked out from the record at upload.
        std::vector<io::HeightRange> expected(static_cast<std::size_t>(b * b));
        io::blockHeightRanges(io::GridView{record.heights.data() + t + 1, t - 2, t}, l.blockQuads(),
                              {record.info.minHeight, record.info.maxHeight}, expected);
        std::vector<float> ranges(static_cast<std::size_t>(2 * b * b));
        pool.blockRanges().readBack({.layer = layer, .width = b, .height = b}, GL_RG, GL_FLOAT,
                                    std::as_writable_bytes(std::span(ranges)));
        for (std::size_t i = 0; i < expected.size(); ++i) {
            EXPECT_EQ(ranges[2 * i], expected[i].low) << "block " << i << " of layer " << layer;
            EXPECT_EQ(ranges[2 * i + 1], expected[i].high)
                << "block " << i << " of layer " << layer;
        }
    }
};

TEST_F(GpuTilePoolTest, CapacityComesFromTheBudget) {
    const std::size_t layerBytes = cache::GpuTilePool::bytesPerLayer(layout());
    EXPECT_EQ(layerBytes, std::size_t{19 * 19 * 4 + 4 * 4 * 16 + 4 * 4 * 8});
    auto created = cache::GpuTilePool::create(
        layout(), {.budgetBytes = 5 * layerBytes + layerBytes / 2, .uploadBudgetBytesPerFrame = 1});
    ASSERT_TRUE(created) << created.error().message;
    const cache::GpuTilePool& pool = created.value();
    EXPECT_EQ(pool.capacity(), 5);
    EXPECT_EQ(pool.layersFree(), 5);
    EXPECT_EQ(pool.layersUsed(), 0);
    EXPECT_EQ(pool.heights().layers(), 5);
    EXPECT_EQ(pool.blockErrors().layers(), 5);
    EXPECT_EQ(pool.heights().internalFormat(), static_cast<GLenum>(GL_R32F));
    EXPECT_EQ(pool.blockErrors().internalFormat(), static_cast<GLenum>(GL_RGBA32F));
    EXPECT_EQ(pool.blockRanges().layers(), 5);
    EXPECT_EQ(pool.blockRanges().internalFormat(), static_cast<GLenum>(GL_RG32F));
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);

    auto tooSmall = cache::GpuTilePool::create(layout(), {.budgetBytes = layerBytes - 1});
    ASSERT_FALSE(tooSmall);
    EXPECT_NE(tooSmall.error().message.find("below one tile layer"), std::string::npos)
        << tooSmall.error().message;

    GLint maxLayers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    auto clamped = cache::GpuTilePool::create(
        layout(), {.budgetBytes = layerBytes * (static_cast<std::size_t>(maxLayers) + 10)});
    ASSERT_TRUE(clamped) << clamped.error().message;
    EXPECT_EQ(clamped.value().capacity(), maxLayers);
}

TEST_F(GpuTilePoolTest, AllocatesUntilFullAndReusesReleasedLayers) {
    cache::GpuTilePool pool = makePool(4, 1 << 20);
    std::vector<int> layers;
    for (int i = 0; i < 4; ++i) {
        const std::optional<int> maybeLayer = pool.allocate({.level = 2, .x = i, .y = 1});
        ASSERT_TRUE(maybeLayer);
        layers.push_back(*maybeLayer);
        EXPECT_FALSE(pool.isResident({.level = 2, .x = i, .y = 1}));
    }
    std::vector<int> sorted = layers;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_EQ(pool.layersUsed(), 4);
    EXPECT_EQ(pool.layersFree(), 0);
    EXPECT_EQ(pool.allocate({.level = 3, .x = 0, .y = 0}), std::nullopt);
    EXPECT_EQ(pool.allocate({.level = 2, .x = 1, .y = 1}), layers[1]) << "already allocated";

    pool.release({.level = 2, .x = 2, .y = 1});
    EXPECT_EQ(pool.layerOf({.level = 2, .x = 2, .y = 1}), std::nullopt);
    EXPECT_EQ(pool.layersFree(), 1);
    EXPECT_EQ(pool.allocate({.level = 3, .x = 0, .y = 0}), layers[2]);
    EXPECT_EQ(pool.layerOf({.level = 3, .x = 0, .y = 0}), layers[2]);
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);
}

TEST_F(GpuTilePoolTest, InvariantsHoldThroughRandomOperations) {
    constexpr int kLayers = 12;
    cache::GpuTilePool pool = makePool(kLayers, 3 * cache::GpuTilePool::bytesPerLayer(layout()));
    std::mt19937 random(1234);
    std::vector<io::PatchId> allocated;
    std::vector<std::pair<io::PatchId, io::PatchRecord>> uploaded;
    pool.beginFrame();
    for (int step = 0; step < 600; ++step) {
        const auto op = random() % 8;
        if (op < 3) {
            const io::PatchId id{.level = 4,
                                 .x = static_cast<std::int64_t>(random() % 30),
                                 .y = static_cast<std::int64_t>(random() % 30)};
            const bool had = pool.layerOf(id).has_value();
            const std::optional<int> maybeLayer = pool.allocate(id);
            if (maybeLayer && !had) {
                allocated.push_back(id);
            }
            if (!maybeLayer) {
                EXPECT_EQ(pool.layersFree(), 0);
            }
        } else if (op < 5 && !allocated.empty()) {
            const std::size_t index = random() % allocated.size();
            pool.release(allocated[index]);
            allocated.erase(allocated.begin() + static_cast<std::ptrdiff_t>(index));
        } else if (op < 7 && !allocated.empty()) {
            const io::PatchId id = allocated[random() % allocated.size()];
            if (pool.upload(makeRecord(id, step))) {
                EXPECT_TRUE(pool.isResident(id));
            }
        } else {
            pool.endFrame();
            pool.beginFrame();
        }
        const auto broken = pool.checkInvariants();
        ASSERT_EQ(broken, std::nullopt) << "step " << step << ": " << *broken;
        ASSERT_EQ(pool.layersUsed(), static_cast<int>(allocated.size()));
        ASSERT_EQ(pool.layersUsed() + pool.layersFree(), kLayers);
    }
    pool.endFrame();
}

TEST_F(GpuTilePoolTest, UploadedTilesRoundTripExactly) {
    cache::GpuTilePool pool = makePool(3, 1 << 20);
    gl::Buffer unrelated = gl::Buffer::create(64, 0, "unrelated unpack buffer");
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, unrelated.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 8);

    pool.beginFrame();
    std::vector<io::PatchRecord> records;
    for (int i = 0; i < 3; ++i) {
        records.push_back(makeRecord({.level = 1, .x = i, .y = 2 * i}));
        ASSERT_TRUE(pool.allocate(records.back().id));
        ASSERT_TRUE(pool.upload(records.back()));
        EXPECT_TRUE(pool.isResident(records.back().id));
    }
    pool.endFrame();
    EXPECT_EQ(pool.frameStats().uploads, 3);
    EXPECT_EQ(pool.frameStats().bytesUploaded, 3 * pool.uploadBytesPerTile());

    GLint binding = 0;
    GLint alignment = 0;
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &binding);
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
    EXPECT_EQ(static_cast<GLuint>(binding), unrelated.id());
    EXPECT_EQ(alignment, 8);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);

    for (const io::PatchRecord& record : records) {
        expectLayerHolds(pool, *pool.layerOf(record.id), record);
    }
}

TEST_F(GpuTilePoolTest, FrameBudgetDefersUploads) {
    const std::size_t tileBytes = cache::GpuTilePool::bytesPerLayer(layout());
    cache::GpuTilePool pool = makePool(4, tileBytes);
    EXPECT_EQ(pool.uploadBytesPerTile(), tileBytes);
    const io::PatchRecord first = makeRecord({.level = 0, .x = 0, .y = 0});
    const io::PatchRecord second = makeRecord({.level = 0, .x = 1, .y = 0});
    ASSERT_TRUE(pool.allocate(first.id));
    ASSERT_TRUE(pool.allocate(second.id));

    pool.beginFrame();
    EXPECT_TRUE(pool.upload(first));
    EXPECT_FALSE(pool.upload(second));
    EXPECT_FALSE(pool.isResident(second.id));
    EXPECT_EQ(pool.frameStats().uploads, 1);
    EXPECT_EQ(pool.frameStats().uploadsDeferred, 1);
    EXPECT_EQ(pool.frameStats().bytesUploaded, tileBytes);
    pool.endFrame();

    pool.beginFrame();
    EXPECT_EQ(pool.frameStats().uploadsDeferred, 0);
    EXPECT_TRUE(pool.upload(second));
    EXPECT_TRUE(pool.isResident(second.id));
    pool.endFrame();

    // A larger budget takes effect at once.
    pool.beginFrame();
    pool.setUploadBudgetBytesPerFrame(2 * tileBytes);
    EXPECT_TRUE(pool.upload(first));
    EXPECT_TRUE(pool.upload(second));
    EXPECT_FALSE(pool.upload(first));
    pool.endFrame();

    expectLayerHolds(pool, *pool.layerOf(first.id), first);
    expectLayerHolds(pool, *pool.layerOf(second.id), second);
}

TEST_F(GpuTilePoolTest, RingWrapsAroundOverManyFramesWithCorrectData) {
    constexpr int kLayers = 40;
    const std::size_t tileBytes = cache::GpuTilePool::bytesPerLayer(layout());
    // A ring of about three tiles, two uploads per frame: it wraps every frame or two.
    cache::GpuTilePool pool = makePool(kLayers, 2 * tileBytes, 3 * tileBytes + 64);
    std::vector<io::PatchRecord> records;
    for (int i = 0; i < kLayers; ++i) {
        records.push_back(makeRecord({.level = 5, .x = i % 7, .y = i / 7}, i));
        ASSERT_TRUE(pool.allocate(records.back().id));
    }
    std::size_t next = 0;
    int frames = 0;
    int stalls = 0;
    while (next < records.size()) {
        ASSERT_LT(frames, 100);
        pool.beginFrame();
        while (next < records.size() && pool.upload(records[next])) {
            ++next;
        }
        stalls += pool.frameStats().ringStalls;
        pool.endFrame();
        ++frames;
        ASSERT_EQ(pool.checkInvariants(), std::nullopt);
    }
    EXPECT_GE(frames, kLayers / 2);
    EXPECT_GE(stalls, 0);
    for (const io::PatchRecord& record : records) {
        EXPECT_TRUE(pool.isResident(record.id));
        expectLayerHolds(pool, *pool.layerOf(record.id), record);
    }
}

// Eviction takes the least recently used layer the current frame has not used; layers a
// frame uses (touched, allocated or uploaded in it) are never taken from it.
TEST_F(GpuTilePoolTest, EvictsTheLeastRecentlyUsedLayerNotUsedThisFrame) {
    cache::GpuTilePool pool = makePool(3, 1 << 20);
    const io::PatchId a{2, 0, 0}, b{2, 1, 0}, c{2, 2, 0}, d{2, 3, 0}, e{2, 0, 1};
    pool.beginFrame();
    for (const io::PatchId& id : {a, b, c}) {
        const auto allocation = pool.allocateEvicting(id);
        ASSERT_TRUE(allocation);
        EXPECT_EQ(allocation->evicted, std::nullopt);
        io::PatchRecord record = makeRecord(id);
        record.info.present = true;
        record.info.maxHeight = static_cast<float>(id.x);
        ASSERT_TRUE(pool.upload(record));
    }
    pool.endFrame();
    ASSERT_NE(pool.info(b), nullptr);
    EXPECT_EQ(pool.info(b)->maxHeight, 1.0f);

    pool.beginFrame();
    pool.touch(b);
    pool.touch(c);
    const int layerOfA = *pool.layerOf(a);
    const auto forD = pool.allocateEvicting(d);
    ASSERT_TRUE(forD);
    EXPECT_EQ(forD->evicted, std::optional<io::PatchId>(a));
    EXPECT_EQ(forD->layer, layerOfA);
    EXPECT_EQ(pool.patchOnLayer(layerOfA), std::optional<io::PatchId>(d));
    EXPECT_FALSE(pool.layerOf(a).has_value());
    EXPECT_EQ(pool.info(d), nullptr) << "not resident before its upload";
    EXPECT_EQ(pool.allocateEvicting(e), std::nullopt) << "b, c and d are used by this frame";
    EXPECT_EQ(pool.frameStats().evictions, 1);
    pool.endFrame();

    pool.beginFrame();
    const auto forE = pool.allocateEvicting(e);
    ASSERT_TRUE(forE);
    EXPECT_EQ(forE->evicted, std::optional<io::PatchId>(b)) << "b was touched before c and d";
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);
    pool.endFrame();
}

TEST_F(GpuTilePoolTest, PinnedCountFollowsPinAndUnpin) {
    // What terrain-stress checks at the end of a run: once the LOD lets go, nothing is pinned.
    cache::GpuTilePool pool = makePool(4, 4 * cache::GpuTilePool::bytesPerLayer(layout()));
    pool.beginFrame();
    const io::PatchId a{.level = 1, .x = 0, .y = 0}, b{.level = 1, .x = 1, .y = 0};
    ASSERT_TRUE(pool.allocate(a));
    ASSERT_TRUE(pool.allocate(b));
    EXPECT_EQ(pool.pinnedCount(), 0);
    pool.pin(a);
    pool.pin(b);
    EXPECT_EQ(pool.pinnedCount(), 2);
    pool.unpin(a);
    EXPECT_EQ(pool.pinnedCount(), 1);
    EXPECT_FALSE(pool.isPinned(a));
    pool.unpin(b);
    EXPECT_EQ(pool.pinnedCount(), 0);
    pool.release(a);
    pool.release(b);
    EXPECT_EQ(pool.layersFree(), pool.capacity());
    EXPECT_EQ(pool.checkInvariants(), std::nullopt);
    pool.endFrame();
}

TEST_F(GpuTilePoolTest, MaxBlockErrorLeavesOutSimplificationsTooCoarseToStore) {
    // A globe face's root tile stores λ(d) = +∞ where its blocks' chords sag more than a
    // half can hold; the control stage never draws those d. The largest error is the
    // largest finite one: an infinite one made every skirt of the frame infinitely deep
    // (a vertex at infinity draws nothing), which opened cracks on the globe.
    cache::GpuTilePool pool = makePool(2, 2 * cache::GpuTilePool::bytesPerLayer(layout()));
    pool.beginFrame();
    const io::PatchId root{.level = 0, .x = 0, .y = 0};
    io::PatchRecord record = makeRecord(root);
    const float inf = std::numeric_limits<float>::infinity();
    float largestFinite = 0.0f;
    for (io::BlockErrors& errors : record.blockErrors) {
        errors[2] = inf;
        errors[3] = inf;
        largestFinite = std::max({largestFinite, errors[0], errors[1]});
    }
    ASSERT_TRUE(pool.allocate(root));
    ASSERT_TRUE(pool.upload(record));
    const std::optional<float> maxError = pool.maxBlockErrorM(root);
    ASSERT_TRUE(maxError.has_value());
    EXPECT_EQ(*maxError, largestFinite);

    // Nothing finite at all: nothing drawable beyond Err(P).
    const io::PatchId other{.level = 0, .x = 1, .y = 0};
    io::PatchRecord unbounded = makeRecord(other);
    for (io::BlockErrors& errors : unbounded.blockErrors) errors.fill(inf);
    ASSERT_TRUE(pool.allocate(other));
    ASSERT_TRUE(pool.upload(unbounded));
    EXPECT_EQ(pool.maxBlockErrorM(other), std::optional<float>(0.0f));
    pool.endFrame();
}

TEST_F(GpuTilePoolTest, KeepsEachUploadsSteepestRises) {
    // What bounds the slopes of a globe patch's flat triangles (io::sampleRises), kept per
    // layer from the heights uploaded; none for a patch that is not resident.
    cache::GpuTilePool pool = makePool(2, 2 * cache::GpuTilePool::bytesPerLayer(layout()));
    pool.beginFrame();
    const io::PatchId root{.level = 0, .x = 0, .y = 0};
    io::PatchRecord record = makeRecord(root);
    const int side = layout().tileSamples();
    record.heights[static_cast<std::size_t>(side + 2)] += 40.0f;  // a spike in the second row
    const io::SampleRises expected =
        io::sampleRises(io::GridView{record.heights.data(), side, side});
    EXPECT_FALSE(pool.sampleRises(root).has_value());
    ASSERT_TRUE(pool.allocate(root));
    ASSERT_TRUE(pool.upload(record));
    const std::optional<io::SampleRises> kept = pool.sampleRises(root);
    ASSERT_TRUE(kept.has_value());
    EXPECT_EQ(kept->east, expected.east);
    EXPECT_EQ(kept->north, expected.north);
    EXPECT_GE(kept->east, 40.0f);
    pool.endFrame();
}

}  // namespace
}  // namespace terrain::test
