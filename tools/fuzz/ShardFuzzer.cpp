// Fuzz target: the shard reader (io::PyramidReader over an OpenEXR shard: the tile offset
// table, the patchInfo tile, heights, mask and block errors, the CRC-32). The input is the
// bytes of the finest shard of a tiny valid pyramid; every patch it holds is read. A
// damaged shard must be an Error naming the shard file, never a crash, a hang or a patch
// whose arrays do not match the layout.
#include "TinyPyramids.h"
#include "terrain/pyramid/PyramidReader.h"

#include <cstdint>
#include <span>

namespace {

struct Target {
    terrain::io::PatchId first;   ///< the shard's first patch
    std::int64_t patchesPerSide;  ///< patches along each side of the shard
    terrain::fuzz::fs::path shard;
};

const Target& target() {
    static const Target t = [] {
        auto reader = terrain::io::PyramidReader::open(terrain::fuzz::tinyPlanarPyramid());
        if (!reader) terrain::fuzz::harnessFailure(reader.error().message);
        const terrain::io::PyramidLayout& layout = reader.value().layout();
        const terrain::io::PatchId first{layout.finestLevel(), 0, 0};
        return Target{first, layout.shardPatches(), reader.value().shardFile(first)};
    }();
    return t;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    terrain::fuzz::addSeed(target().shard, "finest-shard.exr");
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace terrain;
    const Target& t = target();
    fuzz::writeFile(t.shard, std::span(data, size));
    // A new reader per input: a reader keeps its shards open.
    auto reader = io::PyramidReader::open(fuzz::tinyPlanarPyramid());
    if (!reader) fuzz::harnessFailure(reader.error().message);
    const io::PyramidLayout& layout = reader.value().layout();
    const auto samples = static_cast<std::size_t>(layout.tileSamples()) * layout.tileSamples();
    io::PatchRecord record;
    for (std::int64_t y = 0; y < t.patchesPerSide; ++y) {
        for (std::int64_t x = 0; x < t.patchesPerSide; ++x) {
            const io::PatchId id{t.first.level, t.first.x + x, t.first.y + y};
            if (!layout.contains(id)) continue;
            (void)reader.value().patchInfo(id);
            if (!reader.value().readPatch(id, record)) continue;
            fuzz::require(record.heights.size() == samples, "a patch read has its samples");
        }
    }
    return 0;
}
