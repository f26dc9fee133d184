// A pyramid at an http:// URL served by nginx reads exactly as the same folder on disk: the
// manifest, every patch of every level; a later reader confirms instead of fetching; a shard
// missing on the server and a URL with no pyramid give errors naming the URL; an IoThread
// reads a URL with as many threads as one host takes requests at once.
#include "NginxServer.h"
#include "StreamingTestPyramid.h"
#include "TempFolder.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/iothread/IoThread.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/remote/RemoteFiles.h"
#include "terrain/source/ProceduralDems.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;
using test::NginxServer;
using test::TempFolder;

// Every patch of every level, coarsest first.
std::vector<PatchId> everyPatch(const PyramidLayout& layout) {
    std::vector<PatchId> ids;
    for (int level = 0; level < layout.levelCount(); ++level)
        for (std::int64_t y = 0; y < layout.patchesY(level); ++y)
            for (std::int64_t x = 0; x < layout.patchesX(level); ++x)
                ids.push_back({level, static_cast<int>(x), static_cast<int>(y)});
    return ids;
}

class RemotePyramidTest : public ::testing::Test {
protected:
    void SetUp() override {
        TERRAIN_NGINX_OR_SKIP(server);
        // Readers take the cache from the environment, as a tool's do.
        ::setenv("TERRAIN_CACHE_DIR", cache.path().c_str(), 1);
    }
    void TearDown() override { ::unsetenv("TERRAIN_CACHE_DIR"); }

    TempFolder cache;
    const fs::path& local = test::streamingTestPyramid();
    NginxServer server{local.parent_path()};
    const std::string url = server.url(local.filename().string());
};

TEST_F(RemotePyramidTest, EveryPatchReadsAsFromTheFolder) {
    Result<PyramidReader> there = PyramidReader::open(url);
    ASSERT_TRUE(there) << there.error().message;
    Result<PyramidReader> here = PyramidReader::open(local);
    ASSERT_TRUE(here) << here.error().message;
    EXPECT_EQ(toJson(there.value().manifest()), toJson(here.value().manifest()));
    const PyramidLayout& layout = here.value().layout();
    int patches = 0;
    std::set<fs::path> shards;
    for (const PatchId& id : everyPatch(layout)) {
        Result<PatchRecord> a = there.value().readPatch(id);
        Result<PatchRecord> b = here.value().readPatch(id);
        ASSERT_TRUE(a) << a.error().message;
        ASSERT_TRUE(b) << b.error().message;
        ASSERT_EQ(a.value().heights, b.value().heights) << "L" << id.level;
        ASSERT_EQ(a.value().valid, b.value().valid);
        ASSERT_EQ(a.value().blockErrors.size(), b.value().blockErrors.size());
        EXPECT_EQ(a.value().info.error, b.value().info.error);
        shards.insert(here.value().shardFile(id));
        ++patches;
    }
    EXPECT_EQ(patches, 341);
    // Every file came once: the manifest (read once by open) and each shard file.
    const std::size_t files = server.accessLog().size();
    EXPECT_GT(shards.size(), 1u);
    EXPECT_EQ(files, 1 + shards.size());

    // A second reader (a later run) confirms each file with the server; no body comes.
    Result<PyramidReader> again = PyramidReader::open(url);
    ASSERT_TRUE(again) << again.error().message;
    std::set<fs::path> shardsAgain;
    for (int level = 0; level < layout.levelCount(); ++level) {
        ASSERT_TRUE(again.value().readPatch({level, 0, 0}));
        shardsAgain.insert(here.value().shardFile({level, 0, 0}));
    }
    const std::vector<std::string> log = server.accessLog();
    ASSERT_EQ(log.size(), files + 1 + shardsAgain.size())
        << "the manifest and each shard read, each confirmed once";
    for (std::size_t i = files; i < log.size(); ++i)
        EXPECT_NE(log[i].find("\" 304 "), std::string::npos) << log[i];
}

TEST_F(RemotePyramidTest, ReadersOfOneRunConfirmEachFileOnce) {
    // A first run fetches; in a later one, readers sharing what the run has confirmed (an
    // IoThread's reader threads) confirm each file once between them.
    const std::vector<PatchId> patches{{0, 0, 0}, {2, 1, 1}, {4, 3, 2}};
    {
        Result<PyramidReader> first = PyramidReader::open(url);
        ASSERT_TRUE(first) << first.error().message;
        for (const PatchId& id : patches) ASSERT_TRUE(first.value().readPatch(id));
    }
    const std::size_t fetched = server.accessLog().size();
    const auto run = std::make_shared<remote::RemoteRun>();
    std::vector<PyramidReader> readers;
    for (int i = 0; i < 3; ++i) {
        Result<PyramidReader> reader = PyramidReader::open(url, 4, nullptr, run);
        ASSERT_TRUE(reader) << reader.error().message;
        for (const PatchId& id : patches) ASSERT_TRUE(reader.value().readPatch(id));
        readers.push_back(std::move(reader).value());
    }
    const std::vector<std::string> log = server.accessLog();
    EXPECT_EQ(log.size() - fetched, fetched) << "each file the first run fetched, confirmed once";
    for (std::size_t i = fetched; i < log.size(); ++i)
        EXPECT_NE(log[i].find("\" 304 "), std::string::npos) << log[i];
    EXPECT_EQ(readers[1].remoteStats().requests, 0u);
    EXPECT_EQ(readers[2].remoteStats().requests, 0u);
}

TEST_F(RemotePyramidTest, ALargeShardIsReadByRangesPatchByPatch) {
    // Shards of 16 × 16 patches of 65² samples: a finest one holds hundreds of kilobytes, of
    // which a patch is a few.
    TempFolder folder;
    Result<std::unique_ptr<DemReader>> dem = openProceduralDem("procedural:size=1025,seed=9");
    ASSERT_TRUE(dem) << dem.error().message;
    PyramidBuildOptions options;
    options.patchSamples = 65;
    options.shardPatches = 16;
    const fs::path big = folder.path() / "big.pyramid";
    ASSERT_TRUE(buildPyramid(*dem.value(), big, options));
    NginxServer bigServer{folder.path()};
    Result<PyramidReader> there = PyramidReader::open(bigServer.url("big.pyramid"));
    ASSERT_TRUE(there) << there.error().message;
    Result<PyramidReader> here = PyramidReader::open(big);
    ASSERT_TRUE(here) << here.error().message;
    const PyramidLayout& layout = here.value().layout();
    const int finest = layout.finestLevel();
    const PatchId first{finest, 5, 7};
    const std::uint64_t shardBytes = fs::file_size(here.value().shardFile(first));
    ASSERT_GT(shardBytes, 4 * remote::HttpOptions{}.wholeFileBytes()) << "the case tested";

    // Its parent first (its heights are predicted from the parent's, read through the coarser
    // levels' small shards, which come whole), then what the patch itself costs.
    ASSERT_TRUE(there.value().readPatch({finest - 1, first.x / 2, first.y / 2}));
    const remote::RemoteStats before = there.value().remoteStats();
    Result<PatchRecord> a = there.value().readPatch(first);
    ASSERT_TRUE(a) << a.error().message;
    const remote::RemoteStats one = there.value().remoteStats().since(before);
    EXPECT_LE(one.fetchedBytes, shardBytes / 4)
        << "a patch, the shard's head and its patchInfo tile, not the shard";
    EXPECT_LE(one.requests, 3u) << "the shard's head, its patchInfo tile, the patch";

    // Every patch of every level as from the folder.
    for (const PatchId& id : everyPatch(layout)) {
        Result<PatchRecord> got = there.value().readPatch(id);
        Result<PatchRecord> want = here.value().readPatch(id);
        ASSERT_TRUE(got) << got.error().message;
        ASSERT_TRUE(want) << want.error().message;
        ASSERT_EQ(got.value().heights, want.value().heights) << "L" << id.level;
        ASSERT_EQ(got.value().blockErrors, want.value().blockErrors);
        EXPECT_EQ(got.value().info.error, want.value().info.error);
    }
}

TEST_F(RemotePyramidTest, AMissingShardIsAFaultNamingItsUrl) {
    Result<PyramidReader> there = PyramidReader::open(url);
    ASSERT_TRUE(there) << there.error().message;
    const PatchId finest{there.value().layout().levelCount() - 1, 0, 0};
    const fs::path shard = PyramidReader::open(local).value().shardFile(finest);
    const fs::path moved = shard.string() + ".away";
    fs::rename(shard, moved);
    Result<PatchRecord> read = there.value().readPatch(finest);
    fs::rename(moved, shard);
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find(url), std::string::npos) << read.error().message;
    EXPECT_NE(read.error().message.find("HTTP 404"), std::string::npos) << read.error().message;
}

TEST_F(RemotePyramidTest, AUrlWithoutAPyramidSaysSo) {
    const std::string nowhere = server.url("no.pyramid");
    Result<PyramidManifest> manifest = readManifest(nowhere);
    ASSERT_FALSE(manifest);
    EXPECT_NE(manifest.error().message.find(nowhere + ": not a pyramid, or not reachable"),
              std::string::npos)
        << manifest.error().message;
    EXPECT_NE(manifest.error().message.find("HTTP 404"), std::string::npos);
}

TEST_F(RemotePyramidTest, AnIoThreadReadsAUrlWithAsManyThreadsAsAHostTakesRequests) {
    // A read of a URL waits on the network, not on a core: by default the I/O has as many
    // reader threads as requests one host may have under way, so that a teleport's reads
    // ahead travel together (issue 49: 18 frames to full detail at 50 ms on the globe with
    // two threads, 13 with six). A folder keeps the cores' count; a count asked for is kept.
    const auto threadsFor = [](const std::string& location, int asked) {
        IoThreadOptions options;
        options.readerThreads = asked;
        Result<std::unique_ptr<IoThread>> io = IoThread::start(location, options);
        EXPECT_TRUE(io) << io.error().message;
        return io ? io.value()->readerThreads() : 0;
    };
    const int cores = defaultReaderThreads();
    EXPECT_EQ(threadsFor(local.string(), 0), cores);
    EXPECT_EQ(threadsFor(url, 0), std::max(cores, remote::HttpOptions{}.maxPerHost));
    EXPECT_EQ(threadsFor(url, 2), 2);
    ::setenv("TERRAIN_HTTP_MAX_PER_HOST", "9", 1);
    const int nine = threadsFor(url, 0);
    ::unsetenv("TERRAIN_HTTP_MAX_PER_HOST");
    EXPECT_EQ(nine, std::max(cores, 9));
    EXPECT_EQ(defaultReaderThreads(url), std::max(cores, 6));
}

}  // namespace
}  // namespace terrain::io
