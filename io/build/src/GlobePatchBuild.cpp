#include "GlobePatchBuild.h"

#include "BuildFinish.h"
#include "ParallelFor.h"

#include "terrain/pyramid/GlobePatchErrors.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/pyramid/PatchErrors.h"

#include <algorithm>
#include <cmath>
#include <system_error>

namespace terrain::io::detail {

void addPatchesAround(PatchKey key, int level, std::unordered_set<PatchKey>& out) {
    constexpr globe::PatchSide kSides[] = {globe::PatchSide::Left, globe::PatchSide::Right,
                                           globe::PatchSide::Top, globe::PatchSide::Bottom};
    for (const globe::PatchSide side : kSides) {
        const globe::GlobePatchId edge = globe::neighbourOf(idOf(key, level), side).id;
        out.insert(keyOf(edge.face, edge.x, edge.y));
        for (const globe::PatchSide next : kSides) {
            const globe::GlobePatchId beyond = globe::neighbourOf(edge, next).id;
            out.insert(keyOf(beyond.face, beyond.x, beyond.y));
        }
    }
}

double globeHalfStep(const ManifestQuantization& quantization, const PyramidLayout& layout,
                     int faceLevel) {
    return quantization.halfStep(faceLevel + ManifestGlobe::kLevelOffset, layout.finestLevel());
}

void finishGlobePatch(const PyramidLayout& layout, int faceLevel, double error,
                      std::uint8_t presentChildren,
                      const std::optional<ManifestQuantization>& quantization, double quantized,
                      PatchRecord& record) {
    PatchInfo& info = record.info;
    info = PatchInfo{};
    info.present = true;
    summariseDrawnSamples(layout, record.heights, record.valid, info);
    info.presentChildren = presentChildren;
    // Err(P) is measured against the sources on the stored (rounded) surface, so it already
    // holds the rounding: approxError is that measured bound, and quantError says how much
    // of it may be the rounding (δ_l), not something to add (docs/pyramid-format.md,
    // "Lossy storage").
    info.approxError = roundUpToFloat(error);
    info.quantError = 0.0f;
    if (quantization)
        info.quantError =
            roundUpToFloat(std::max(globeHalfStep(*quantization, layout, faceLevel), quantized));
    info.error = info.approxError;

    const int tile = layout.tileSamples();
    const GridView interior{record.heights.data() + tile + 1, layout.patchSamples(), tile};
    record.blockErrors.resize(
        static_cast<std::size_t>(layout.blocksPerSide() * layout.blocksPerSide()));
    globePatchBlockErrors(interior, layout.blockQuads(), faceLevel, info.minHeight,
                          record.blockErrors);
}

Status writeGlobeShard(const std::filesystem::path& folder, const PyramidLayout& layout,
                       const ShardId& shard, const std::vector<const PatchRecord*>& records,
                       const ShardWriterOptions& options,
                       const std::optional<ManifestQuantization>& quantization, unsigned threads) {
    const std::filesystem::path path = folder / layout.shardPath(shard);
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) return Error{path.parent_path().string() + ": cannot create folder: " + ec.message()};
    ShardWriterOptions shardOptions = options;
    if (quantization)
        shardOptions.units.quantizerStep = quantization->step(shard.level, layout.finestLevel());
    auto writer = ShardWriter::create(path, layout, shard, true, shardOptions);
    if (!writer) return writer.error();
    // Coded and compressed on every thread, written in order.
    std::vector<EncodedPatch> encoded(records.size());
    parallelFor(std::ssize(records), threads, [&](std::int64_t i) {
        const auto k = static_cast<std::size_t>(i);
        encodePatch(*records[k], {}, layout, true, shardOptions, encoded[k]);
    });
    for (const EncodedPatch& patch : encoded)
        if (Status written = writer.value().writeEncoded(patch); !written) return written;
    return writer.value().finish();
}

ManifestGlobeSource globeSourceOf(const GeographicGrid& grid, std::string input) {
    const double east = grid.eastDeg() > 180.0 ? grid.eastDeg() - 360.0 : grid.eastDeg();
    return ManifestGlobeSource{.input = std::move(input),
                               .west = grid.wrapsLongitude() ? -180.0 : grid.westDeg(),
                               .south = std::max(-90.0, grid.southDeg()),
                               .east = grid.wrapsLongitude() ? 180.0 : east,
                               .north = std::min(90.0, grid.northDeg()),
                               .native = {}};
}

PyramidManifest globeManifest(const PyramidLayout& layout, int faceFinestLevel,
                              std::vector<ManifestGlobeSource> sources,
                              std::span<DemReader* const> readers) {
    TERRAIN_ASSERT(!sources.empty(), "globeManifest needs a source");
    PyramidManifest m = PyramidManifest::forLayout(layout);
    m.formatVersion = PyramidManifest::kGlobeFormatVersion;
    const ManifestGlobeSource& finest = sources.front();
    m.globe = ManifestGlobe{.faceFinestLevel = faceFinestLevel,
                            .west = finest.west,
                            .south = finest.south,
                            .east = finest.east,
                            .north = finest.north,
                            .seams = {},
                            .sources = std::move(sources),
                            .seaLevelM = 0.0};
    describeSources(m, readers);
    // The mask always: samples beyond the sources are not data on a globe.
    m.noData.present = true;
    return m;
}

}  // namespace terrain::io::detail
