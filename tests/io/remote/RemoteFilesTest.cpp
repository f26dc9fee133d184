// RemoteFiles against a real static server: a file is fetched once, confirmed with a 304 by a
// later reader, fetched again when the server's copy changes, never used truncated, served
// from the cache when the server is gone, and the cache stays within its bound and cleans
// up what a killed process leaves. Through a fault proxy (FaultProxy.h): every network
// fault is survived with the files whole, lost packets only delay them, and a process killed
// (SIGKILL) while it writes a body into the cache leaves the cache usable.
#include "FaultProxy.h"
#include "NginxServer.h"
#include "TempFolder.h"
#include "terrain/remote/RemoteFiles.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace terrain::remote {
namespace {

namespace fs = std::filesystem;
using test::FaultPlan;
using test::FaultProxy;
using test::NginxServer;
using test::ProxyFault;
using test::TempFolder;

std::string contentsOf(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

void writeFile(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
}

// Retries without waiting, so a test of a failure takes no time.
// What AProcessKilledWhileWritingABodyLeavesTheCacheUsable's viewer process fetches, and
// into which cache.
constexpr const char* kChildUrl = "TERRAIN_TEST_REMOTE_CHILD_URL";
constexpr const char* kChildCache = "TERRAIN_TEST_REMOTE_CHILD_CACHE";

HttpOptions quickHttp() {
    HttpOptions options;
    options.retries = 2;
    options.firstBackoff = std::chrono::milliseconds(1);
    options.connectTimeout = std::chrono::milliseconds(2000);
    options.requestTimeout = std::chrono::milliseconds(5000);
    return options;
}

class RemoteFilesTest : public ::testing::Test {
protected:
    void SetUp() override { TERRAIN_NGINX_OR_SKIP(server); }
    std::unique_ptr<RemoteFiles> files(std::uint64_t maxBytes = std::uint64_t{1} << 30,
                                       HttpOptions http = quickHttp()) {
        Result<std::unique_ptr<RemoteFiles>> opened =
            RemoteFiles::open({cache.path(), maxBytes}, http);
        EXPECT_TRUE(opened) << opened.error().message;
        return std::move(opened).value();
    }

    // Files prefix0 … prefix(count − 1) on the server, file i holding body(i).
    void writeFiles(const std::string& prefix, int count,
                    const std::function<std::string(int)>& body) {
        for (int i = 0; i < count; ++i)
            writeFile(root.path() / (prefix + std::to_string(i)), body(i));
    }
    // Each of those files read through `reader` from urlOf(its name): every one whole.
    static void expectEachWhole(RemoteFiles& reader,
                                const std::function<std::string(const std::string&)>& urlOf,
                                const std::string& prefix, int count,
                                const std::function<std::string(int)>& body) {
        for (int i = 0; i < count; ++i) {
            Result<fs::path> copy = reader.localCopy(urlOf(prefix + std::to_string(i)));
            ASSERT_TRUE(copy) << copy.error().message;
            EXPECT_EQ(contentsOf(copy.value()), body(i)) << "file " << i;
        }
    }

    TempFolder root;
    TempFolder cache;
    NginxServer server{root.path()};
};

TEST_F(RemoteFilesTest, FetchesOnceThenConfirmsWithTheServer) {
    writeFile(root.path() / "p" / "a.bin", std::string(5000, 'a'));
    const std::string url = server.url("p/a.bin");
    auto first = files();
    Result<fs::path> copy = first->localCopy(url);
    ASSERT_TRUE(copy) << copy.error().message;
    EXPECT_EQ(contentsOf(copy.value()), std::string(5000, 'a'));
    EXPECT_EQ(first->stats().fetched, 1u);
    EXPECT_EQ(first->stats().fetchedBytes, 5000u);
    // The same reader again: no request at all.
    ASSERT_TRUE(first->localCopy(url));
    EXPECT_EQ(first->stats().requests, 1u);
    EXPECT_EQ(first->stats().cacheHits, 1u);

    // A later reader (a later run): one conditional request, answered 304, no body.
    auto second = files();
    Result<fs::path> again = second->localCopy(url);
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_EQ(contentsOf(again.value()), std::string(5000, 'a'));
    EXPECT_EQ(second->stats().notModified, 1u);
    EXPECT_EQ(second->stats().fetchedBytes, 0u);
    const std::vector<std::string> log = server.accessLog();
    ASSERT_EQ(log.size(), 2u);
    EXPECT_NE(log[1].find("\" 304 "), std::string::npos) << log[1];
}

TEST_F(RemoteFilesTest, AChangedFileOnTheServerIsFetchedAgain) {
    writeFile(root.path() / "m.json", "old");
    const std::string url = server.url("m.json");
    ASSERT_TRUE(files()->localCopy(url));
    // Rebuilt: another size, so nginx's ETag (mtime and size) differs even within a second.
    writeFile(root.path() / "m.json", "rebuilt");
    auto later = files();
    Result<fs::path> copy = later->localCopy(url);
    ASSERT_TRUE(copy) << copy.error().message;
    EXPECT_EQ(contentsOf(copy.value()), "rebuilt");
    EXPECT_EQ(later->stats().fetched, 1u);
}

// A file whose every byte differs from its neighbours', so a block read from the wrong place
// shows.
std::string patterned(std::size_t bytes, std::uint32_t seed) {
    std::string body(bytes, '\0');
    for (std::size_t i = 0; i < bytes; ++i)
        body[i] = static_cast<char>((static_cast<std::uint32_t>(i) * 2654435761u + seed) >> 13);
    return body;
}

std::string rangeRead(RemoteFile& file, std::uint64_t offset, std::size_t bytes) {
    std::string out(bytes, '\0');
    Status read = file.read(offset, std::span<char>(out));
    EXPECT_TRUE(read) << read.error().message;
    return out;
}

// nginx's access log line's status ("GET /a HTTP/1.1" 206 …).
bool answered(const std::string& logLine, int status) {
    return logLine.find("\" " + std::to_string(status) + " ") != std::string::npos;
}

TEST_F(RemoteFilesTest, ALargeFileReadByRangesFetchesTheBlocksReadsNeedOnce) {
    constexpr std::size_t kSize = 1'000'000;  // not a multiple of a block
    const std::string body = patterned(kSize, 1);
    writeFile(root.path() / "big.exr", body);
    const std::string url = server.url("big.exr");
    auto reader = files();
    Result<std::unique_ptr<RemoteFile>> opened = reader->openRanged(url);
    ASSERT_TRUE(opened) << opened.error().message;
    RemoteFile& file = *opened.value();
    EXPECT_EQ(file.size(), kSize);
    EXPECT_EQ(reader->stats().fetchedBytes, HttpOptions{}.rangeBytes) << "only the head";
    EXPECT_EQ(rangeRead(file, 10, 1000), body.substr(10, 1000)) << "from the head";
    EXPECT_EQ(reader->stats().requests, 1u);

    EXPECT_EQ(rangeRead(file, 600'000, 100), body.substr(600'000, 100));
    EXPECT_EQ(reader->stats().requests, 2u);
    EXPECT_EQ(reader->stats().fetchedBytes, 2 * HttpOptions{}.rangeBytes)
        << "the block read and the ones after it, a fetch's worth";
    // Within what that fetch brought: no request.
    EXPECT_EQ(rangeRead(file, 600'000 + 30'000, 20'000), body.substr(630'000, 20'000));
    EXPECT_EQ(reader->stats().requests, 2u);
    // The file's last bytes: the range ends at its end.
    EXPECT_EQ(rangeRead(file, kSize - 5, 5), body.substr(kSize - 5));
    EXPECT_EQ(reader->stats().requests, 3u);
    std::string beyond(10, '\0');
    EXPECT_FALSE(file.read(kSize - 5, std::span<char>(beyond)));

    // A later run: one conditional request for the head (304), then the blocks the cache holds
    // come from it and only the others from the server.
    auto later = files();
    Result<std::unique_ptr<RemoteFile>> again = later->openRanged(url);
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_EQ(later->stats().notModified, 1u);
    EXPECT_EQ(rangeRead(*again.value(), 600'000, 100), body.substr(600'000, 100));
    EXPECT_EQ(later->stats().requests, 1u);
    EXPECT_EQ(rangeRead(*again.value(), 300'000, 100), body.substr(300'000, 100));
    EXPECT_EQ(later->stats().requests, 2u);
    const std::vector<std::string> log = server.accessLog();
    ASSERT_EQ(log.size(), 5u);
    for (std::size_t i : {0, 1, 2, 4}) EXPECT_TRUE(answered(log[i], 206)) << log[i];
    EXPECT_TRUE(answered(log[3], 304)) << log[3];

    // Read to the end, the entry is the whole file: a copy as localCopy gives it.
    for (std::uint64_t at = 0; at < kSize; at += 100'000)
        ASSERT_EQ(rangeRead(*again.value(), at, std::min<std::size_t>(100'000, kSize - at)),
                  body.substr(at, 100'000));
    Result<fs::path> copy = files()->localCopy(url);
    ASSERT_TRUE(copy) << copy.error().message;
    EXPECT_EQ(contentsOf(copy.value()), body);
    EXPECT_TRUE(answered(server.accessLog().back(), 304)) << "confirmed, not fetched again";
}

TEST_F(RemoteFilesTest, ReadingOnThroughAFileDoublesItsRanges) {
    // 3 MB read front to back in 20 KB reads: after the head, ranges of 128, 256, 512 KiB,
    // 1 MiB, then the rest (at most 2 MiB), not 46 ranges of 64 KiB.
    const std::string body = patterned(3'000'000, 10);
    writeFile(root.path() / "seq.exr", body);
    auto reader = files();
    Result<std::unique_ptr<RemoteFile>> opened = reader->openRanged(server.url("seq.exr"));
    ASSERT_TRUE(opened) << opened.error().message;
    for (std::uint64_t at = 0; at < body.size(); at += 20'000)
        ASSERT_EQ(rangeRead(*opened.value(), at, std::min<std::size_t>(20'000, body.size() - at)),
                  body.substr(at, 20'000));
    EXPECT_EQ(reader->stats().requests, 6u);
    EXPECT_EQ(reader->stats().fetchedBytes, body.size());
}

TEST_F(RemoteFilesTest, SmallFilesReadByRangesComeWhole) {
    const std::string small = patterned(HttpOptions{}.rangeBytes - 7, 2);
    const std::string middling = patterned(HttpOptions{}.wholeFileBytes() - 3, 3);
    writeFile(root.path() / "s.exr", small);
    writeFile(root.path() / "m.exr", middling);
    auto reader = files();
    Result<std::unique_ptr<RemoteFile>> s = reader->openRanged(server.url("s.exr"));
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(reader->stats().requests, 1u);
    Result<std::unique_ptr<RemoteFile>> m = reader->openRanged(server.url("m.exr"));
    ASSERT_TRUE(m) << m.error().message;
    EXPECT_EQ(reader->stats().requests, 3u) << "its head, then the rest";
    EXPECT_EQ(rangeRead(*s.value(), 0, small.size()), small);
    EXPECT_EQ(rangeRead(*m.value(), 0, middling.size()), middling);
    EXPECT_EQ(reader->stats().requests, 3u);
    EXPECT_EQ(reader->stats().fetchedBytes, small.size() + middling.size());
}

TEST_F(RemoteFilesTest, AFileRebuiltWhileReadByRangesIsRefusedThenReadAnew) {
    const std::string before = patterned(700'000, 4);
    writeFile(root.path() / "r.exr", before);
    const std::string url = server.url("r.exr");
    auto reader = files();
    Result<std::unique_ptr<RemoteFile>> opened = reader->openRanged(url);
    ASSERT_TRUE(opened) << opened.error().message;
    // Rebuilt on the server: its blocks must not be mixed with the old head's.
    const std::string after = patterned(800'000, 5);
    writeFile(root.path() / "r.exr", after);
    std::string out(100, '\0');
    const Status read = opened.value()->read(500'000, std::span<char>(out));
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find("changed on the server"), std::string::npos)
        << read.error().message;
    // The next run sees the new version.
    auto later = files();
    Result<std::unique_ptr<RemoteFile>> anew = later->openRanged(url);
    ASSERT_TRUE(anew) << anew.error().message;
    EXPECT_EQ(anew.value()->size(), after.size());
    EXPECT_EQ(rangeRead(*anew.value(), 0, 100), after.substr(0, 100));
    EXPECT_EQ(rangeRead(*anew.value(), 500'000, 100), after.substr(500'000, 100));
}

TEST_F(RemoteFilesTest, ATruncatedCacheEntryIsNeverUsed) {
    writeFile(root.path() / "t.bin", std::string(4096, 't'));
    const std::string url = server.url("t.bin");
    Result<fs::path> copy = files()->localCopy(url);
    ASSERT_TRUE(copy);
    fs::resize_file(copy.value(), 100);  // a crash or a full disk mid-way, say
    auto later = files();
    Result<fs::path> again = later->localCopy(url);
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_EQ(contentsOf(again.value()), std::string(4096, 't'));
    EXPECT_EQ(later->stats().fetched, 1u);  // a miss: fetched whole, not confirmed
}

TEST_F(RemoteFilesTest, AMissingFileIsAnErrorNamingTheUrlAndTheStatus) {
    const std::string url = server.url("nowhere/manifest.json");
    Result<fs::path> copy = files()->localCopy(url);
    ASSERT_FALSE(copy);
    EXPECT_NE(copy.error().message.find(url), std::string::npos) << copy.error().message;
    EXPECT_NE(copy.error().message.find("HTTP 404"), std::string::npos) << copy.error().message;
}

TEST_F(RemoteFilesTest, WithTheServerGoneACachedCopyServesAndAnUncachedFileFails) {
    writeFile(root.path() / "kept.bin", "kept");
    writeFile(root.path() / "never.bin", "never");
    ASSERT_TRUE(files()->localCopy(server.url("kept.bin")));
    const std::string kept = server.url("kept.bin"), never = server.url("never.bin");
    server.stop();
    auto offline = files();
    Result<fs::path> copy = offline->localCopy(kept);
    ASSERT_TRUE(copy) << copy.error().message;
    EXPECT_EQ(contentsOf(copy.value()), "kept");
    EXPECT_EQ(offline->stats().staleServed, 1u);
    EXPECT_EQ(offline->stats().retries, 2u);  // the retries were made before giving up
    Result<fs::path> missing = offline->localCopy(never);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find(never), std::string::npos);
    EXPECT_NE(missing.error().message.find("3 attempts"), std::string::npos)
        << missing.error().message;
}

TEST_F(RemoteFilesTest, TheCacheStaysWithinItsBoundLeastRecentlyUsedFirst) {
    for (int i = 0; i < 6; ++i)
        writeFile(root.path() / ("f" + std::to_string(i)), std::string(1000, char('0' + i)));
    auto reader = files(3500);  // three files fit
    for (int i = 0; i < 6; ++i) {
        Result<fs::path> copy = reader->localCopy(server.url("f" + std::to_string(i)));
        ASSERT_TRUE(copy) << copy.error().message;
        // Each file's copy is whole when returned, even as the cache trims others.
        EXPECT_EQ(contentsOf(copy.value()), std::string(1000, char('0' + i)));
    }
    std::uintmax_t dataBytes = 0;
    int entries = 0;
    for (const auto& entry : fs::recursive_directory_iterator(cache.path())) {
        if (!entry.is_regular_file() || entry.path().filename() == "lock") continue;
        if (entry.path().extension() == ".meta")
            ++entries;
        else
            dataBytes += entry.file_size();
    }
    EXPECT_EQ(entries, 3);
    EXPECT_LE(dataBytes, 3500u);
    // The three most recent are the ones kept: asked again, they need no body.
    auto later = files(3500);
    for (int i = 3; i < 6; ++i) ASSERT_TRUE(later->localCopy(server.url("f" + std::to_string(i))));
    EXPECT_EQ(later->stats().fetched, 0u);
    EXPECT_EQ(later->stats().notModified, 3u);
}

TEST_F(RemoteFilesTest, WhatAKilledWriterLeavesIsIgnoredThenRemoved) {
    writeFile(root.path() / "w.bin", "whole");
    const std::string url = server.url("w.bin");
    ASSERT_TRUE(files()->localCopy(url));
    // A process killed mid-write leaves a temporary file, or a data file no meta names.
    fs::path folder;
    for (const auto& entry : fs::recursive_directory_iterator(cache.path()))
        if (entry.path().extension() == ".meta") folder = entry.path().parent_path();
    ASSERT_FALSE(folder.empty());
    const fs::path temporary = folder / ".w.bin.tmp-999999-0.0123456789abcdef";
    const fs::path orphan = folder / "w.bin.fedcba9876543210";
    writeFile(temporary, "half");
    writeFile(orphan, "half");
    const auto longAgo = fs::file_time_type::clock::now() - std::chrono::hours(1);
    fs::last_write_time(temporary, longAgo);
    fs::last_write_time(orphan, longAgo);

    auto later = files();
    Result<fs::path> copy = later->localCopy(url);
    ASSERT_TRUE(copy) << copy.error().message;
    EXPECT_EQ(contentsOf(copy.value()), "whole");
    // The next store trims: the leftovers go, the entry stays.
    writeFile(root.path() / "x.bin", "x");
    ASSERT_TRUE(later->localCopy(server.url("x.bin")));
    EXPECT_FALSE(fs::exists(temporary));
    EXPECT_FALSE(fs::exists(orphan));
    EXPECT_TRUE(fs::exists(copy.value()));
}

TEST_F(RemoteFilesTest, EveryNetworkFaultIsSurvivedAndNoFileIsKeptHalf) {
    // Every other request faulted, the five kinds in turn: a reset, a closed connection, a
    // 503, a body cut short, a body trickled out.
    FaultProxy proxy(server.port(), FaultPlan{.faultEvery = 2});
    ASSERT_TRUE(proxy.ready());
    constexpr int kFiles = 12;
    auto body = [](int i) { return std::string(20000 + 1000 * i, char('a' + i)); };
    writeFiles("n", kFiles, body);
    auto reader = files();
    expectEachWhole(
        *reader, [&](const std::string& name) { return proxy.url(name); }, "n", kFiles, body);
    for (ProxyFault kind : FaultPlan{}.kinds)
        EXPECT_GE(proxy.faulted(kind), 1) << "fault " << static_cast<int>(kind) << " never met";
    EXPECT_EQ(reader->stats().fetched, static_cast<std::uint64_t>(kFiles));
    // Retried by us: at least the 503s and the cut bodies (a reused connection that dies
    // before any answer, libcurl itself may retry on a new one).
    EXPECT_GE(reader->stats().retries, 2u);
    // What the faults left in the cache is whole: a later run confirms every file, no body.
    auto later = files();
    expectEachWhole(
        *later, [&](const std::string& name) { return server.url(name); }, "n", kFiles, body);
}

TEST_F(RemoteFilesTest, RangesSurviveEveryNetworkFaultWithTheirBytesRight) {
    // Every third request faulted, the five kinds in turn, on one file read range by range
    // (the retry of a faulted request is never the next faulted one).
    FaultProxy proxy(server.port(), FaultPlan{.faultEvery = 3, .oncePerPath = false});
    ASSERT_TRUE(proxy.ready());
    const std::string body = patterned(1'500'000, 6);
    writeFile(root.path() / "f.exr", body);
    auto reader = files();
    Result<std::unique_ptr<RemoteFile>> opened = reader->openRanged(proxy.url("f.exr"));
    ASSERT_TRUE(opened) << opened.error().message;
    // From the end backwards: each read a fetch of its own (none follows the one before).
    constexpr int kReads = 16;
    for (int i = kReads; i >= 1; --i) {
        const std::uint64_t at = static_cast<std::uint64_t>(i) * 90'000 + 777;
        ASSERT_EQ(rangeRead(*opened.value(), at, 3000), body.substr(at, 3000)) << "read " << i;
    }
    for (ProxyFault kind : FaultPlan{}.kinds)
        EXPECT_GE(proxy.faulted(kind), 1) << "fault " << static_cast<int>(kind) << " never met";
    EXPECT_EQ(reader->stats().fetched, 1u + kReads);
    // What came through the faults and was kept is right: a later run, the faults over, reads
    // every byte, the kept blocks from the cache.
    proxy.setPlan(FaultPlan{});
    auto later = files();
    Result<std::unique_ptr<RemoteFile>> again = later->openRanged(proxy.url("f.exr"));
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_EQ(rangeRead(*again.value(), 0, body.size()), body);
    EXPECT_EQ(later->stats().notModified, 1u);
    EXPECT_LT(later->stats().fetchedBytes, body.size());
}

TEST_F(RemoteFilesTest, LostPacketsDelayFilesAndCorruptNone) {
    // 5 % of the packets lost, each stalling its stream as TCP's retransmission does (1 ms
    // here): a stall is no failure, so every file arrives whole, fetched once, not retried.
    FaultProxy proxy(server.port(), FaultPlan{.segmentLoss = 0.05,
                                              .retransmitDelay = std::chrono::milliseconds(1)});
    ASSERT_TRUE(proxy.ready());
    constexpr int kFiles = 8;
    auto body = [](int i) { return std::string(40000 + 997 * i, char('k' + i)); };
    writeFiles("l", kFiles, body);
    auto reader = files();
    expectEachWhole(
        *reader, [&](const std::string& name) { return proxy.url(name); }, "l", kFiles, body);
    EXPECT_GT(proxy.lostPackets(), 0) << "the case tested: some of ~230 packets lost";
    EXPECT_EQ(reader->stats().fetched, static_cast<std::uint64_t>(kFiles));
    EXPECT_EQ(reader->stats().retries, 0u);
}

TEST_F(RemoteFilesTest, AnswersPacedByACongestionWindowWithLossesArriveWhole) {
    // The benches' network (remote_arrival_bench.py): answers a window at a time from 4
    // segments, a (1 ms) round trip between windows, 2 % of packets lost halving the window.
    FaultProxy proxy(server.port(), FaultPlan{.latency = std::chrono::milliseconds(1),
                                              .segmentLoss = 0.02,
                                              .retransmitDelay = std::chrono::milliseconds(1),
                                              .initialWindow = 4});
    ASSERT_TRUE(proxy.ready());
    constexpr int kFiles = 4;
    auto body = [](int i) { return patterned(60000 + 4999 * static_cast<std::size_t>(i), 7); };
    writeFiles("w", kFiles, body);
    auto reader = files();
    expectEachWhole(
        *reader, [&](const std::string& name) { return proxy.url(name); }, "w", kFiles, body);
    const std::string big = patterned(900'000, 8);
    writeFile(root.path() / "w.exr", big);
    Result<std::unique_ptr<RemoteFile>> opened = reader->openRanged(proxy.url("w.exr"));
    ASSERT_TRUE(opened) << opened.error().message;
    EXPECT_EQ(rangeRead(*opened.value(), 123'456, 200'000), big.substr(123'456, 200'000));
    EXPECT_GT(proxy.lostPackets(), 0) << "the case tested";
    EXPECT_EQ(reader->stats().retries, 0u);
}

TEST_F(RemoteFilesTest, ConnectionsShareTheLinksRate) {
    // The benches' user's line (remote_arrival_bench.py --link-mbps): two readers fetching a
    // 250 KB file each at once over a 2 MB/s link that both connections share get both no
    // sooner than 500 KB at 2 MB/s allows, a quarter of a second; the link only delays.
    FaultProxy proxy(server.port(), FaultPlan{.initialWindow = 1000, .linkBytesPerSecond = 2e6});
    ASSERT_TRUE(proxy.ready());
    const std::string first = patterned(250'000, 3), second = patterned(250'000, 4);
    writeFile(root.path() / "first.bin", first);
    writeFile(root.path() / "second.bin", second);
    std::unique_ptr<RemoteFiles> a = files(), b = files();
    Result<fs::path> copyA = Error{"not run"}, copyB = Error{"not run"};
    const auto start = std::chrono::steady_clock::now();
    std::thread one([&] { copyA = a->localCopy(proxy.url("first.bin")); });
    std::thread two([&] { copyB = b->localCopy(proxy.url("second.bin")); });
    one.join();
    two.join();
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    ASSERT_TRUE(copyA) << copyA.error().message;
    ASSERT_TRUE(copyB) << copyB.error().message;
    EXPECT_EQ(contentsOf(copyA.value()), first);
    EXPECT_EQ(contentsOf(copyB.value()), second);
    EXPECT_GE(took.count(), 0.25) << "500 KB through a 2 MB/s link";
}

TEST_F(RemoteFilesTest, ReadersWantingOneFileAtOnceFetchItOnce) {
    // Two readers (the I/O thread's reader threads, or two programs) on one cache want the
    // same new file at once; the answer takes 300 ms. One fetches it, the other waits and
    // uses that copy (or, had it come only after, confirms it with a 304): one body.
    FaultProxy proxy(server.port(), FaultPlan{.latency = std::chrono::milliseconds(300)});
    ASSERT_TRUE(proxy.ready());
    const std::string body(100000, 's');
    writeFile(root.path() / "shared.bin", body);
    const std::string url = proxy.url("shared.bin");
    std::unique_ptr<RemoteFiles> a = files(), b = files();
    Result<fs::path> copyA = Error{"not run"}, copyB = Error{"not run"};
    std::thread first([&] { copyA = a->localCopy(url); });
    std::thread second([&] { copyB = b->localCopy(url); });
    first.join();
    second.join();
    ASSERT_TRUE(copyA) << copyA.error().message;
    ASSERT_TRUE(copyB) << copyB.error().message;
    EXPECT_EQ(contentsOf(copyA.value()), body);
    EXPECT_EQ(contentsOf(copyB.value()), body);
    EXPECT_EQ(a->stats().fetched + b->stats().fetched, 1u);
    EXPECT_EQ(a->stats().fetchedBytes + b->stats().fetchedBytes, body.size());
    EXPECT_LE(proxy.requests(), 2);
}

TEST_F(RemoteFilesTest, ReadersOfARunWantingOneRangeAtOnceFetchItOnce) {
    // Two reader threads of one run (sharing a RemoteRun) want the same bytes of a file read
    // by ranges at once; an answer takes 300 ms. One fetches them, the other waits for that
    // fetch and reads them from the cache: one range, not two.
    FaultProxy proxy(server.port(), FaultPlan{.latency = std::chrono::milliseconds(300)});
    ASSERT_TRUE(proxy.ready());
    const std::string body = patterned(1'000'000, 11);
    writeFile(root.path() / "together.exr", body);
    const std::string url = proxy.url("together.exr");
    const auto run = std::make_shared<RemoteRun>();
    const auto reader = [&] {
        Result<std::unique_ptr<RemoteFiles>> opened =
            RemoteFiles::open({cache.path(), std::uint64_t{1} << 30}, quickHttp(), run);
        EXPECT_TRUE(opened) << opened.error().message;
        return std::move(opened).value();
    };
    std::unique_ptr<RemoteFiles> a = reader(), b = reader();
    Result<std::unique_ptr<RemoteFile>> fileA = a->openRanged(url);
    ASSERT_TRUE(fileA) << fileA.error().message;
    Result<std::unique_ptr<RemoteFile>> fileB = b->openRanged(url);
    ASSERT_TRUE(fileB) << fileB.error().message;
    EXPECT_EQ(b->stats().requests, 0u) << "confirmed by the run already";
    std::string outA, outB;
    std::thread first([&] { outA = rangeRead(*fileA.value(), 500'000, 30'000); });
    std::thread second([&] { outB = rangeRead(*fileB.value(), 500'000, 30'000); });
    first.join();
    second.join();
    EXPECT_EQ(outA, body.substr(500'000, 30'000));
    EXPECT_EQ(outB, outA);
    EXPECT_EQ(proxy.requests(), 2) << "the head, and one range for both";
    EXPECT_EQ(a->stats().fetchedBytes + b->stats().fetchedBytes, 2 * HttpOptions{}.rangeBytes);
}

TEST_F(RemoteFilesTest, AtMostMaxPerHostRequestsGoToOneHostAtOnce) {
    // Four readers (four RemoteFiles, as four reader threads have) each want a different new
    // file from one host, every answer 60 ms away; the process lets one request at a time go
    // to the host (HttpOptions::maxPerHost = 1), so the server never answers two at once,
    // and every file still arrives. The readers of a process share the limit.
    FaultProxy proxy(server.port(), FaultPlan{.latency = std::chrono::milliseconds(60)});
    ASSERT_TRUE(proxy.ready());
    HttpOptions oneAtATime = quickHttp();
    oneAtATime.maxPerHost = 1;
    constexpr int kReaders = 4;
    std::vector<std::unique_ptr<RemoteFiles>> readers;
    std::vector<Result<fs::path>> copies(kReaders, Error{"not run"});
    for (int r = 0; r < kReaders; ++r) {
        writeFile(root.path() / ("file" + std::to_string(r)), std::string(5000, char('a' + r)));
        readers.push_back(files(std::uint64_t{1} << 30, oneAtATime));
    }
    std::vector<std::thread> threads;
    for (int r = 0; r < kReaders; ++r)
        threads.emplace_back([&, r] {
            copies[static_cast<std::size_t>(r)] = readers[static_cast<std::size_t>(r)]->localCopy(
                proxy.url("file" + std::to_string(r)));
        });
    for (std::thread& t : threads) t.join();
    for (int r = 0; r < kReaders; ++r) {
        const Result<fs::path>& copy = copies[static_cast<std::size_t>(r)];
        ASSERT_TRUE(copy) << copy.error().message;
        EXPECT_EQ(contentsOf(copy.value()), std::string(5000, char('a' + r)));
    }
    EXPECT_EQ(proxy.requests(), kReaders);
    EXPECT_EQ(proxy.maxInFlight(), 1);
}

TEST(HttpOptionsTest, TheLimitPerHostIsReadFromTheEnvironmentAndCheckedThere) {
    ::setenv("TERRAIN_HTTP_MAX_PER_HOST", "3", 1);
    Result<HttpOptions> three = HttpOptions::fromEnvironment();
    ASSERT_TRUE(three) << three.error().message;
    EXPECT_EQ(three.value().maxPerHost, 3);
    ::setenv("TERRAIN_HTTP_MAX_PER_HOST", "0", 1);
    Result<HttpOptions> none = HttpOptions::fromEnvironment();
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("TERRAIN_HTTP_MAX_PER_HOST=\"0\""), std::string::npos)
        << none.error().message;
    ::unsetenv("TERRAIN_HTTP_MAX_PER_HOST");
    Result<HttpOptions> defaults = HttpOptions::fromEnvironment();
    ASSERT_TRUE(defaults);
    EXPECT_EQ(defaults.value().maxPerHost, HttpOptions{}.maxPerHost);
}

TEST(HttpOptionsTest, TheRangeSizeIsReadFromTheEnvironmentAndCheckedThere) {
    ::setenv("TERRAIN_HTTP_RANGE_BYTES", "256K", 1);
    Result<HttpOptions> quarter = HttpOptions::fromEnvironment();
    ASSERT_TRUE(quarter) << quarter.error().message;
    EXPECT_EQ(quarter.value().rangeBytes, 256u * 1024);
    ::setenv("TERRAIN_HTTP_RANGE_BYTES", "0", 1);
    Result<HttpOptions> whole = HttpOptions::fromEnvironment();
    ASSERT_TRUE(whole) << whole.error().message;
    EXPECT_EQ(whole.value().rangeBytes, 0u);
    ::setenv("TERRAIN_HTTP_RANGE_BYTES", "1000", 1);
    Result<HttpOptions> odd = HttpOptions::fromEnvironment();
    ::unsetenv("TERRAIN_HTTP_RANGE_BYTES");
    ASSERT_FALSE(odd);
    EXPECT_NE(odd.error().message.find("TERRAIN_HTTP_RANGE_BYTES=\"1000\""), std::string::npos)
        << odd.error().message;
}

TEST_F(RemoteFilesTest, WithoutRangesAFileReadByRangesComesWhole) {
    const std::string body = patterned(900'000, 9);
    writeFile(root.path() / "h.exr", body);
    HttpOptions http = quickHttp();
    http.rangeBytes = 0;
    auto reader = files(std::uint64_t{1} << 30, http);
    Result<std::unique_ptr<RemoteFile>> opened = reader->openRanged(server.url("h.exr"));
    ASSERT_TRUE(opened) << opened.error().message;
    EXPECT_EQ(rangeRead(*opened.value(), 500'000, 100), body.substr(500'000, 100));
    EXPECT_EQ(reader->stats().requests, 1u);
    EXPECT_EQ(reader->stats().fetchedBytes, body.size());
    EXPECT_TRUE(answered(server.accessLog().back(), 200)) << server.accessLog().back();
}

TEST_F(RemoteFilesTest, AProcessKilledWhileWritingABodyLeavesTheCacheUsable) {
    FaultProxy proxy(server.port());
    ASSERT_TRUE(proxy.ready());
    const std::string url = proxy.url("k.bin");
    const std::string before(200000, 'v'), after(300000, 'w');
    writeFile(root.path() / "k.bin", before);
    ASSERT_TRUE(files()->localCopy(url));
    // The pyramid is rebuilt; a viewer starts fetching the new file and is killed half-way
    // through the body (the proxy holds the rest back until the kill is done).
    writeFile(root.path() / "k.bin", after);
    proxy.setPlan(FaultPlan{.faultEvery = 1, .kinds = {ProxyFault::HoldBody}});
    // The viewer is this test program run afresh (spawned, not forked: a fork of this
    // process, whose server and proxy threads may hold a lock at that moment, could wait on
    // it for ever), running only the disabled case below.
    const std::string urlVariable = std::string(kChildUrl) + "=" + url;
    const std::string cacheVariable = std::string(kChildCache) + "=" + cache.path().string();
    std::vector<char*> environment;
    for (char** entry = environ; *entry != nullptr; ++entry) environment.push_back(*entry);
    environment.push_back(const_cast<char*>(urlVariable.c_str()));
    environment.push_back(const_cast<char*>(cacheVariable.c_str()));
    environment.push_back(nullptr);
    const char* argv[] = {"RemoteFilesTest", "--gtest_also_run_disabled_tests",
                          "--gtest_filter=RemoteFilesChild.DISABLED_FetchesForItsParent", nullptr};
    // Its own report would interleave with this one's: to /dev/null.
    posix_spawn_file_actions_t quiet;
    ::posix_spawn_file_actions_init(&quiet);
    ::posix_spawn_file_actions_addopen(&quiet, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    pid_t child = 0;
    const int spawned = ::posix_spawn(&child, "/proc/self/exe", &quiet, nullptr,
                                      const_cast<char**>(argv), environment.data());
    ::posix_spawn_file_actions_destroy(&quiet);
    ASSERT_EQ(spawned, 0);
    const bool midWrite =
        proxy.waitForFaults(ProxyFault::HoldBody, 1, std::chrono::milliseconds(60000));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    proxy.release();
    ASSERT_TRUE(midWrite) << "the killed process never reached the body";
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);

    // With the server failing, the copy from before the kill serves, whole.
    proxy.setPlan(
        FaultPlan{.faultEvery = 1, .oncePerPath = false, .kinds = {ProxyFault::ServerError}});
    auto offline = files();
    Result<fs::path> old = offline->localCopy(url);
    ASSERT_TRUE(old) << old.error().message;
    EXPECT_EQ(contentsOf(old.value()), before);
    EXPECT_EQ(offline->stats().staleServed, 1u);
    // With the server back, the new file comes whole.
    proxy.setPlan(FaultPlan{});
    auto online = files();
    Result<fs::path> fresh = online->localCopy(url);
    ASSERT_TRUE(fresh) << fresh.error().message;
    EXPECT_EQ(contentsOf(fresh.value()), after);
    EXPECT_EQ(online->stats().fetched, 1u);
}

// The viewer AProcessKilledWhileWritingABodyLeavesTheCacheUsable spawns and kills: disabled,
// so it runs only there, where the variables name the file and the cache.
TEST(RemoteFilesChild, DISABLED_FetchesForItsParent) {
    const char* url = std::getenv(kChildUrl);
    const char* cachePath = std::getenv(kChildCache);
    ASSERT_NE(url, nullptr);
    ASSERT_NE(cachePath, nullptr);
    Result<std::unique_ptr<RemoteFiles>> viewer =
        RemoteFiles::open({cachePath, std::uint64_t{1} << 30}, quickHttp());
    if (viewer) (void)viewer.value()->localCopy(url);
    ::_exit(0);
}

TEST(RemoteLocation, OnlyHttpAndHttpsAreRemote) {
    EXPECT_TRUE(isRemoteLocation("http://example.org/p.pyramid"));
    EXPECT_TRUE(isRemoteLocation("HTTPS://example.org/p.pyramid"));
    EXPECT_FALSE(isRemoteLocation("/data/p.pyramid"));
    EXPECT_FALSE(isRemoteLocation("planet:seed=4"));
    EXPECT_FALSE(isRemoteLocation("http://"));
    EXPECT_EQ(joinUrl("http://h/p.pyramid", "manifest.json"), "http://h/p.pyramid/manifest.json");
    EXPECT_EQ(joinUrl("http://h/p.pyramid/", "manifest.json"), "http://h/p.pyramid/manifest.json");
}

TEST(RemoteOptions, BadEnvironmentValuesAreNamed) {
    ::setenv("TERRAIN_CACHE_BYTES", "lots", 1);
    Result<CacheOptions> cache = CacheOptions::fromEnvironment();
    ::unsetenv("TERRAIN_CACHE_BYTES");
    ASSERT_FALSE(cache);
    EXPECT_NE(cache.error().message.find("TERRAIN_CACHE_BYTES=\"lots\""), std::string::npos);
    ::setenv("TERRAIN_CACHE_BYTES", "2G", 1);
    Result<CacheOptions> twoGiB = CacheOptions::fromEnvironment();
    ::unsetenv("TERRAIN_CACHE_BYTES");
    ASSERT_TRUE(twoGiB);
    EXPECT_EQ(twoGiB.value().maxBytes, std::uint64_t{2} << 30);
    ::setenv("TERRAIN_HTTP_RETRIES", "-1", 1);
    Result<HttpOptions> http = HttpOptions::fromEnvironment();
    ::unsetenv("TERRAIN_HTTP_RETRIES");
    ASSERT_FALSE(http);
    EXPECT_NE(http.error().message.find("TERRAIN_HTTP_RETRIES"), std::string::npos);
}

}  // namespace
}  // namespace terrain::remote
