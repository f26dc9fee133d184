// terrain-shard-bench: throughput of the pyramid format alone. Writes a whole pyramid of
// the requested size (every level, every shard) from a pool of real patch tiles cut from a
// DEM, then reads every patch back; prints patches/s and bytes. No error bounds are
// computed beyond the block errors of the pool, so the numbers are the format's own cost.
#include "CommandLine.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/NoDataFill.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/pyramid/ShardWriter.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

namespace {

namespace fs = std::filesystem;
namespace io = terrain::io;
using terrain::Error;
using terrain::Result;
using terrain::Status;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU time of the whole process (all threads), user + system: a load-independent cost.
double cpuSeconds() {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    const auto seconds = [](const timeval& t) {
        return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6;
    };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// Tiles of (N + 2)² samples cut at random places of the DEM, with their block errors.
Result<std::vector<io::PatchRecord>> patchPool(io::DemReader& dem, const io::PyramidLayout& layout,
                                               int count, bool withMask, std::uint32_t seed) {
    const io::DemInfo& info = dem.info();
    const int tile = layout.tileSamples();
    const int n = layout.patchSamples();
    if (info.width < tile || info.height < tile)
        return Error{fmt::format("{}: {} × {} samples, smaller than a {}² tile", info.path,
                                 info.width, info.height, tile)};
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::int64_t> px(0, info.width - tile), py(0, info.height - tile);
    std::vector<io::PatchRecord> pool;
    std::vector<std::uint8_t> valid(static_cast<std::size_t>(tile) *
                                    static_cast<std::size_t>(tile));
    for (int p = 0; p < count; ++p) {
        io::PatchRecord r;
        r.heights.resize(static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile));
        if (Status read = dem.readWindow(px(rng), py(rng), tile, tile, r.heights); !read)
            return read.error();
        // The tile's voids filled from what the tile holds of their rims.
        io::fillNoData(tile, tile, r.heights, valid);
        if (withMask) r.valid = valid;
        // Filled samples count as no-data only where the mask records them.
        r.info.present = true;
        io::summariseDrawnSamples(layout, r.heights, r.valid, r.info);
        r.blockErrors.resize(
            static_cast<std::size_t>(layout.blocksPerSide() * layout.blocksPerSide()));
        io::patchBlockErrors({r.heights.data() + tile + 1, n, tile}, layout.blockQuads(),
                             r.blockErrors);
        pool.push_back(std::move(r));
    }
    return pool;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "terrain-shard-bench: write a whole pyramid of the given size with the pyramid format's "
        "ShardWriter from a pool of real patch tiles cut out of a DEM, then read every patch "
        "back with PyramidReader; prints patches/s for both. The result is a valid pyramid "
        "(terrain-inspect --verify passes on it) whose patches repeat the pool's tiles."};
    std::string dem = "procedural:size=4097";
    std::string output;
    std::int64_t size = 16385;
    int compressionLevel = terrain::io::ShardWriterOptions::kDefaultCompressionLevel;
    int poolSize = 64;
    bool withMask = false;
    bool keep = false;
    bool skipRead = false;
    bool json = false;
    app.add_option("--dem", dem, "DEM to cut the patch pool from (any input openDem reads)")
        ->capture_default_str();
    app.add_option("-o,--output", output, "Pyramid folder to write (replaced)")->required();
    app.add_option("--size", size, "Raster side of the pyramid written, samples")
        ->capture_default_str();
    app.add_option("--compression-level", compressionLevel,
                   "zstd level of the patch payloads, 1..19; 0: uncompressed")
        ->capture_default_str();
    app.add_option("--pool", poolSize, "Distinct patch tiles")->capture_default_str();
    app.add_flag("--mask", withMask, "Write the V mask (a pyramid with no-data)");
    app.add_flag("--keep", keep, "Keep the pyramid (default: removed at the end)");
    app.add_flag("--no-read", skipRead, "Skip the read-back");
    app.add_flag("--json", json, "Print a JSON summary");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;
    const auto fail = [](const std::string& message) {
        std::fprintf(stderr, "terrain-shard-bench: %s\n", message.c_str());
        return 1;
    };

    auto layout = io::PyramidLayout::create(size, size);
    if (!layout) return fail(layout.error().message);
    const io::PyramidLayout& L = layout.value();
    // Patches never overhang the raster, so every pool tile is a whole valid patch.
    const std::int64_t finest = L.patchesX(L.finestLevel());
    if ((size - 1) % L.patchQuads() != 0 || (finest & (finest - 1)) != 0)
        return fail(fmt::format("--size {}: use 128 · 2^k + 1 (129, 257, ..., 16385)", size));
    auto reader = io::openDem({dem});
    if (!reader) return fail(reader.error().message);
    auto pool = patchPool(*reader.value(), L, poolSize, withMask, 1);
    if (!pool) return fail(pool.error().message);

    std::error_code ec;
    fs::remove_all(output, ec);
    fs::create_directories(output, ec);
    if (ec) return fail(fmt::format("{}: cannot create the folder: {}", output, ec.message()));

    io::PyramidManifest manifest = io::PyramidManifest::forLayout(L);
    manifest.noData.present = withMask;
    manifest.source = {{dem}, reader.value()->info().readerName, reader.value()->info().sampleType};
    manifest.build = {"terrain-shard-bench", "0.1.0", 0.0};
    // Err_Appr grows by 1 m a level from the finest up: nested as the spec requires.
    io::ShardWriterOptions options;
    options.compressionLevel = compressionLevel;
    std::int64_t patches = 0;
    double minHeight = std::numeric_limits<double>::infinity(), maxHeight = -minHeight;
    const auto writeStart = Clock::now();
    const double writeCpuStart = cpuSeconds();
    for (int l = 0; l <= L.finestLevel(); ++l) {
        const auto approx = static_cast<float>(L.finestLevel() - l);
        for (std::int64_t sy = 0; sy < L.shardsY(l); ++sy)
            for (std::int64_t sx = 0; sx < L.shardsX(l); ++sx) {
                const io::ShardId s{l, sx, sy};
                auto writer = io::ShardWriter::create(fs::path(output) / L.shardPath(s), L, s,
                                                      withMask, options);
                if (!writer) return fail(writer.error().message);
                for (int ty = 0; ty < L.shardCountY(s); ++ty)
                    for (int tx = 0; tx < L.shardCountX(s); ++tx) {
                        const io::PatchId id{l, L.shardFirstX(s) + tx, L.shardFirstY(s) + ty};
                        io::PatchRecord& r = pool.value()[static_cast<std::size_t>(
                            (id.x * 7919 + id.y * 104729 + l) % poolSize)];
                        r.id = id;
                        r.info.approxError = approx;
                        r.info.error = approx;
                        minHeight = std::min(minHeight, static_cast<double>(r.info.minHeight));
                        maxHeight = std::max(maxHeight, static_cast<double>(r.info.maxHeight));
                        if (Status ok = writer.value().writePatch(r); !ok)
                            return fail(ok.error().message);
                        ++patches;
                    }
                if (Status ok = writer.value().finish(); !ok) return fail(ok.error().message);
            }
        manifest.levels[static_cast<std::size_t>(l)].maxError = approx;
    }
    const double writeSeconds = secondsSince(writeStart);
    const double writeCpu = cpuSeconds() - writeCpuStart;
    manifest.statistics = {minHeight, maxHeight, size * size, static_cast<double>(L.finestLevel())};
    manifest.build.seconds = writeSeconds;
    if (Status ok = io::writeManifest(output, manifest); !ok) return fail(ok.error().message);

    std::uintmax_t bytes = 0;
    for (const auto& entry : fs::recursive_directory_iterator(output))
        if (entry.is_regular_file()) bytes += entry.file_size();
    const double rawBytes =
        static_cast<double>(patches) *
        (static_cast<double>(L.tileSamples() * L.tileSamples()) * (withMask ? 6.0 : 4.0) +
         static_cast<double>(L.blocksPerSide() * L.blocksPerSide()) * 16.0);

    double readSeconds = 0.0, readCpu = 0.0;
    if (!skipRead) {
        auto pyramid = io::PyramidReader::open(output);
        if (!pyramid) return fail(pyramid.error().message);
        io::PatchRecord record;
        const auto readStart = Clock::now();
        const double readCpuStart = cpuSeconds();
        for (int l = 0; l <= L.finestLevel(); ++l)
            for (std::int64_t y = 0; y < L.patchesY(l); ++y)
                for (std::int64_t x = 0; x < L.patchesX(l); ++x)
                    if (Status ok = pyramid.value().readPatch({l, x, y}, record); !ok)
                        return fail(ok.error().message);
        readSeconds = secondsSince(readStart);
        readCpu = cpuSeconds() - readCpuStart;
    }
    if (!keep) fs::remove_all(output, ec);

    const double writeRate = static_cast<double>(patches) / writeSeconds;
    const double readRate = skipRead ? 0.0 : static_cast<double>(patches) / readSeconds;
    if (json) {
        nlohmann::ordered_json j;
        j["dem"] = dem;
        j["size"] = size;
        j["patches"] = patches;
        j["compressionLevel"] = compressionLevel;
        j["mask"] = withMask;
        j["bytes"] = bytes;
        j["compressionRatio"] = rawBytes / static_cast<double>(bytes);
        j["writeSeconds"] = writeSeconds;
        j["writeCpuSeconds"] = writeCpu;
        j["writeCpuMsPerPatch"] = writeCpu * 1e3 / static_cast<double>(patches);
        j["writePatchesPerSecond"] = writeRate;
        j["readSeconds"] =
            skipRead ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(readSeconds);
        j["readCpuMsPerPatch"] =
            skipRead ? nlohmann::ordered_json(nullptr)
                     : nlohmann::ordered_json(readCpu * 1e3 / static_cast<double>(patches));
        j["readPatchesPerSecond"] =
            skipRead ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(readRate);
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        fmt::print("{} patches of {}² ({} × {} raster, {}), compression level {}{}\n", patches,
                   L.tileSamples(), size, size, dem, compressionLevel,
                   withMask ? ", with mask" : "");
        fmt::print(
            "write: {:.2f} s, {:.0f} patches/s, {:.3f} CPU ms/patch, {:.1f} MB on disk "
            "(ratio {:.2f})\n",
            writeSeconds, writeRate, writeCpu * 1e3 / static_cast<double>(patches),
            static_cast<double>(bytes) * 1e-6, rawBytes / static_cast<double>(bytes));
        if (!skipRead)
            fmt::print(
                "read:  {:.2f} s, {:.0f} patches/s, {:.3f} CPU ms/patch (one reader, one "
                "thread, CRC checked)\n",
                readSeconds, readRate, readCpu * 1e3 / static_cast<double>(patches));
    }
    return 0;
}
