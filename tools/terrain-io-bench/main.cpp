// terrain-io-bench: how many tiles per second the streaming I/O reads and decodes from a
// pyramid, through the same IoThread the runtime uses (queue, read, CRC check, completion
// hand-over, record recycling), with its reader threads (--reader-threads, the runtime's
// default unless given). Shard files are read once first, so the figure
// is from the page cache: the cost of the format and the thread, not of the disk. On a
// globe pyramid the patches are its present ones, from the six faces down (the virtual
// planet's are generated: the figure is then the planet's cost a tile). With --imagery, an
// imagery layer's tiles instead: decoded and given their mips as the I/O thread does, on one
// thread, the two timed apart (ImageryDecodeBench.h).
#include "CommandLine.h"
#include "ImageryDecodeBench.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/iothread/IoThread.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/PyramidReader.h"

#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using namespace terrain;

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-io-bench: {}\n", message);
    return 1;
}

/// Every patch of the pyramid, shuffled: a flight asks for tiles all over the shards, and a
/// patch's parent, which its heights are predicted from, is rarely among the last read.
std::vector<io::PatchId> shuffledPatches(const io::PyramidLayout& layout, std::uint64_t seed) {
    std::vector<io::PatchId> ids;
    for (int level = 0; level <= layout.finestLevel(); ++level) {
        for (std::int64_t y = 0; y < layout.patchesY(level); ++y) {
            for (std::int64_t x = 0; x < layout.patchesX(level); ++x) ids.push_back({level, x, y});
        }
    }
    std::shuffle(ids.begin(), ids.end(), std::mt19937_64(seed));
    return ids;
}

/// Every patch, each after its parent: depth first from the root, the four children in
/// shuffled order, as the streaming refines (it splits only into children of a resident
/// patch).
void appendSubtree(const io::PyramidLayout& layout, const io::PatchId& id, std::mt19937_64& rng,
                   std::vector<io::PatchId>& ids) {
    ids.push_back(id);
    if (id.level == layout.finestLevel()) return;
    std::vector<io::PatchId> children;
    for (int c = 0; c < 4; ++c) {
        const io::PatchId child{id.level + 1, 2 * id.x + c % 2, 2 * id.y + c / 2};
        if (layout.contains(child)) children.push_back(child);
    }
    std::shuffle(children.begin(), children.end(), rng);
    for (const io::PatchId& child : children) appendSubtree(layout, child, rng, ids);
}

std::vector<io::PatchId> parentFirstPatches(const io::PyramidLayout& layout, std::uint64_t seed) {
    std::vector<io::PatchId> ids;
    std::mt19937_64 rng(seed);
    appendSubtree(layout, io::PatchId{0, 0, 0}, rng, ids);
    return ids;
}

/// A globe's present patches, level by level from the six faces (each after its parent), at
/// most `most` of them: a globe is sparse, and the virtual planet has 10^8 patches.
Result<std::vector<io::PatchId>> presentGlobePatches(io::PyramidReader& reader, std::size_t most) {
    std::vector<io::PatchId> ids;
    for (int face = 0; face < globe::kCubeFaces && ids.size() < most; ++face)
        ids.push_back(io::layoutPatchOf({face, 0, 0, 0}));
    for (std::size_t next = 0; next < ids.size() && ids.size() < most; ++next) {
        auto info = reader.patchInfo(ids[next]);
        if (!info) return info.error();
        const globe::GlobePatchId id = io::globePatchOf(ids[next]);
        for (int c = 0; c < 4 && ids.size() < most; ++c)
            if ((info.value().presentChildren >> c) & 1)
                ids.push_back(io::layoutPatchOf(
                    {id.face, id.level + 1, 2 * id.x + (c & 1), 2 * id.y + (c >> 1)}));
    }
    return ids;
}

/// --imagery: the layer's decode figures, on stdout as JSON with `json`, and a line on stderr.
int runImageryDecode(const tools::ImageryDecodeOptions& options, bool json) {
    auto measured = tools::measureImageryDecode(options);
    if (!measured) return fail(measured.error().message);
    const tools::ImageryDecodeFigures& f = measured.value();
    const double tiles = static_cast<double>(f.tiles);
    const double decodePerS = tiles / f.decodeS;
    const double withMipsPerS = tiles / f.seconds();
    constexpr double kMiB = 1024.0 * 1024.0;
    // File bytes a tile on average (its share of the tables too); 0 for a generated layer.
    const double fileBytesPerTile =
        f.indexTiles > 0 ? static_cast<double>(f.fileBytes) / static_cast<double>(f.indexTiles)
                         : 0.0;
    const auto texelBytes = static_cast<double>(io::kImageryTileBytes);
    const auto mipBytes = static_cast<double>(io::kImageryMipChainBytes);
    if (json) {
        const nlohmann::json out{
            {"tool", "terrain-io-bench"},
            {"pyramid", options.pyramid.string()},
            {"imagery_layer", options.layer},
            {"io_threads", 1},
            {"distinct_tiles", f.distinctTiles},
            {"tiles", f.tiles},
            {"file_bytes_per_tile", fileBytesPerTile},
            {"decode_seconds", f.decodeS},
            {"mips_seconds", f.mipsS},
            {"decode_tiles_per_s", decodePerS},
            {"decode_compressed_mib_per_s", decodePerS * fileBytesPerTile / kMiB},
            {"decode_texel_mib_per_s", decodePerS * texelBytes / kMiB},
            {"decode_mips_tiles_per_s", withMipsPerS},
            {"decode_mips_texel_mib_per_s", withMipsPerS * (texelBytes + mipBytes) / kMiB},
            {"decode_us_per_tile", 1e6 * f.decodeS / tiles},
            {"mips_us_per_tile", 1e6 * f.mipsS / tiles},
        };
        std::puts(out.dump(2).c_str());
    }
    fmt::print(stderr,
               "terrain-io-bench: imagery layer \"{}\": {} tiles ({} distinct, {:.0f} file bytes "
               "each) on 1 thread: decode {:.0f} tiles/s ({:.1f} MiB/s of files, {:.1f} MiB/s of "
               "texels, {:.0f} µs a tile); decode and mips {:.0f} tiles/s ({:.1f} MiB/s of "
               "texels and mips; mips {:.0f} µs a tile)\n",
               options.layer, f.tiles, f.distinctTiles, fileBytesPerTile, decodePerS,
               decodePerS * fileBytesPerTile / kMiB, decodePerS * texelBytes / kMiB,
               1e6 * f.decodeS / tiles, withMipsPerS, withMipsPerS * (texelBytes + mipBytes) / kMiB,
               1e6 * f.mipsS / tiles);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Tiles per second read and decoded by the streaming I/O threads from the page "
        "cache, through the runtime's IoThread; with --imagery, an imagery layer's tiles "
        "decoded and given their mips as the I/O thread does."};
    std::string pyramid;
    double seconds = 5.0;
    std::size_t maxPatches = 20000;
    std::size_t inFlight = 64;
    int openShards = io::IoThreadOptions{}.maxOpenShards;
    int readerThreads = 0;
    double parentCacheMiB = 0.0;
    bool json = false;
    std::string order = "shuffled";
    app.add_option("pyramid", pyramid, "Pyramid folder")->required();
    app.add_option("--order", order,
                   "shuffled: every patch in a random order; parent-first: every patch after its "
                   "parent, depth first, as the streaming refines")
        ->capture_default_str()
        ->check(CLI::IsMember({"shuffled", "parent-first"}));
    app.add_option("--seconds", seconds, "Measure for at least this long")->capture_default_str();
    app.add_option("--max-patches", maxPatches, "Cycle over at most this many patches")
        ->capture_default_str();
    app.add_option("--in-flight", inFlight, "Requests kept submitted at once")
        ->capture_default_str()
        ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 20));
    app.add_option("--open-shards", openShards,
                   "Shard files the I/O thread keeps open (the runtime's default)")
        ->capture_default_str()
        ->check(CLI::Range(1, 4096));
    app.add_option("--reader-threads", readerThreads,
                   "IoThread reader threads, each reading and decoding (0, the runtime's "
                   "default: min(hardware threads, 4); a pyramid at a URL at least as many as "
                   "TERRAIN_HTTP_MAX_PER_HOST, 6)")
        ->capture_default_str()
        ->check(CLI::Range(0, 64));
    app.add_option("--parent-cache-mib", parentCacheMiB,
                   "Decoded parents the reader threads keep for their children, in one cache "
                   "they share (0: the runtime's default, 4 MiB a reader thread)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1048576.0));
    app.add_flag("--json", json, "Print a JSON summary on stdout");
    std::string imagery;
    app.add_option("--imagery", imagery,
                   "Measure this imagery layer's tiles instead (every present tile in a shuffled "
                   "order on this thread: read and decoded, then its mips; the two timed apart; "
                   "--max-patches caps the tiles)");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;
    if (!imagery.empty())
        return runImageryDecode(
            {.pyramid = pyramid, .layer = imagery, .seconds = seconds, .maxTiles = maxPatches},
            json);

    auto reader = io::PyramidReader::open(pyramid);
    if (!reader) return fail(reader.error().message);
    std::vector<io::PatchId> ids;
    if (reader.value().manifest().globe) {
        auto present = presentGlobePatches(reader.value(), maxPatches);
        if (!present) return fail(present.error().message);
        ids = std::move(present).value();
        if (order == "shuffled") std::shuffle(ids.begin(), ids.end(), std::mt19937_64(1));
    } else {
        ids = order == "shuffled" ? shuffledPatches(reader.value().layout(), 1)
                                  : parentFirstPatches(reader.value().layout(), 1);
    }
    if (ids.size() > maxPatches) ids.resize(maxPatches);

    // Warm the page cache (and check every patch reads) with a plain reader, in the same
    // order, counting the parents it had to read again to decode a child.
    io::PatchRecord record;
    for (const io::PatchId& id : ids) {
        if (auto read = reader.value().readPatch(id, record); !read)
            return fail(read.error().message);
    }
    const double parentReadsPerPatch =
        static_cast<double>(reader.value().parentReads()) / static_cast<double>(ids.size());
    const std::size_t tileBytes = record.heights.size() * sizeof(float) + record.valid.size() +
                                  record.blockErrors.size() * sizeof(io::BlockErrors);

    io::IoThreadOptions options;
    options.maxUnpolled = inFlight;
    options.maxOpenShards = openShards;
    options.readerThreads = readerThreads;
    options.parentCacheBytes = static_cast<std::size_t>(parentCacheMiB * 1024.0 * 1024.0);
    options = options.resolvedFor(pyramid);
    readerThreads = options.readerThreads;
    const double cacheMiB =
        static_cast<double>(options.sharedParentCacheBytes()) / (1024.0 * 1024.0);
    auto started = io::IoThread::start(pyramid, options);
    if (!started) return fail(started.error().message);
    io::IoThread& thread = *started.value();
    std::vector<io::Completion> done;
    done.reserve(inFlight);
    std::size_t next = 0, submitted = 0, completed = 0, failed = 0;
    // Counts only the submits that made a request: with several reader threads a patch
    // submitted again may still be read (its completions end out of order), and then the
    // submit only re-prioritises it and the next patch is taken instead.
    const auto submitOne = [&] {
        for (std::size_t tries = 0; tries < ids.size(); ++tries) {
            const bool created = thread.submit(ids[next], 0.0f);
            next = (next + 1) % ids.size();
            if (created) {
                ++submitted;
                return;
            }
        }
    };
    const auto start = Clock::now();
    double elapsed = 0.0;
    for (std::size_t i = 0; i < std::min(inFlight, ids.size()); ++i) submitOne();
    while (elapsed < seconds || completed + failed < submitted) {
        done.clear();
        // Waits on the threads' event rather than spinning: a spinning caller takes a core
        // from the reader threads on a small machine.
        if (thread.poll(done) == 0) thread.waitForCompletion(std::chrono::milliseconds(100));
        for (io::Completion& c : done) {
            c.status == io::CompletionStatus::Completed ? ++completed : ++failed;
            thread.recycle(std::move(c.record));
            // Keep the queue full while measuring; a patch is resubmitted only after it ended.
            if (elapsed < seconds) submitOne();
        }
        elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    }
    const double tilesPerS = static_cast<double>(completed) / elapsed;
    // The parents the reader threads read again, sharing their cache, per patch measured.
    const double threadParentReadsPerPatch =
        completed == 0
            ? 0.0
            : static_cast<double>(thread.stats().parentReads) / static_cast<double>(completed);
    const auto& layout = reader.value().layout();
    if (json) {
        const nlohmann::json out{
            {"tool", "terrain-io-bench"},
            {"pyramid", pyramid},
            {"patch_samples", layout.patchSamples()},
            {"tile_bytes", tileBytes},
            {"distinct_patches", ids.size()},
            {"order", order},
            {"parent_reads_per_patch", parentReadsPerPatch},
            {"parent_cache_mib", cacheMiB},
            {"io_parent_reads_per_patch", threadParentReadsPerPatch},
            {"io_threads", readerThreads},
            {"open_shards", openShards},
            {"tiles", completed},
            {"failed", failed},
            {"seconds", elapsed},
            {"tiles_per_s", tilesPerS},
            {"mib_per_s", tilesPerS * static_cast<double>(tileBytes) / (1024.0 * 1024.0)},
            {"us_per_tile", 1e6 / tilesPerS},
        };
        std::puts(out.dump(2).c_str());
    }
    fmt::print(stderr,
               "terrain-io-bench: {} tiles of {}² in {:.2f} s on {} I/O thread{}: {:.0f} tiles/s "
               "({:.1f} MiB/s, {:.0f} µs per tile; {} order, {:.2f} parents read again per "
               "patch with {:.0f} MiB of parents shared by the threads){}\n",
               completed, layout.patchSamples() + 2, elapsed, readerThreads,
               readerThreads == 1 ? "" : "s", tilesPerS,
               tilesPerS * static_cast<double>(tileBytes) / (1024.0 * 1024.0), 1e6 / tilesPerS,
               order, threadParentReadsPerPatch, cacheMiB,
               failed > 0 ? fmt::format(", {} failed", failed) : "");
    return failed == 0 ? 0 : 1;
}
