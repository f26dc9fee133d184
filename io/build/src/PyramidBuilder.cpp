// The streaming pyramid build (LevelBuilder.h): one pass per level, finest first, each in
// bands of two patch rows across the level's full width; or, where such a band exceeds the
// memory budget, the same passes shard by shard (PyramidShards.h).
#include "terrain/build/PyramidBuilder.h"

#include "BuildOutput.h"
#include "LevelBuilder.h"
#include "PlanarBuildTotals.h"
#include "SourceCoverage.h"
#include "terrain/build/PyramidShards.h"

#include <fmt/core.h>

#include <chrono>

namespace terrain::io {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace detail {

bool planarMaskStored(const DemInfo& dem) {
    // The mask is stored when the source declares a no-data value. NaN samples of a float
    // source that declares none are filled and counted all the same, but not masked: the
    // mask costs 2 bytes a sample (half) in every tile, and the build streams, so it has to
    // decide before it has seen the samples.
    // A resampled source is masked too: the resampled grid's corners outside it are no-data.
    return dem.noDataValue.has_value() || dem.resampledFrom.has_value();
}

std::uint64_t planarBandBytes(const PyramidLayout& l, std::int64_t bandPatches) {
    // Two patch rows of padded samples (heights and mask), the reader's window, and the
    // patch records.
    const auto bandBytes =
        std::uint64_t(2 * l.patchQuads() + 3) * std::uint64_t(bandPatches * l.patchQuads() + 3) * 5;
    const auto recordBytes =
        std::uint64_t(2 * bandPatches) * std::uint64_t(l.tileSamples() * l.tileSamples()) * 5;
    return 2 * bandBytes + recordBytes + (std::uint64_t{64} << 20);
}

Result<PyramidBuildSummary> finishPlanarBuild(const DemReader& reader, const PyramidLayout& layout,
                                              const PlanarBuildTotals& totals,
                                              const fs::path& folder) {
    const DemInfo& dem = reader.info();
    const DemStatistics& stats = totals.statistics;
    PyramidBuildSummary summary;
    PyramidManifest& m = summary.manifest;
    m = PyramidManifest::forLayout(layout);
    m.georeference = dem.georeference;
    m.vertical = dem.vertical;
    m.noData.present = planarMaskStored(dem);
    m.noData.sourceValue = dem.noDataValue;
    m.noData.samples = stats.noDataSamples;
    m.statistics.minHeight = stats.validSamples > 0 ? stats.minHeight : 0.0;
    m.statistics.maxHeight = stats.validSamples > 0 ? stats.maxHeight : 0.0;
    m.statistics.validSamples = stats.validSamples;
    m.statistics.rootError = totals.levelMaxError.at(0);  // the one root patch's Err(P)
    for (ManifestLevel& level : m.levels)
        level.maxError = totals.levelMaxError.at(static_cast<std::size_t>(level.level));
    m.source.inputs = dem.inputs;
    m.source.reader = dem.readerName;
    m.source.sampleType = dem.sampleType;
    m.source.band = dem.band;
    m.source.bandCount = dem.bandCount;
    m.source.rowsFlipped = dem.rowsFlipped;
    m.source.columnsFlipped = dem.columnsFlipped;
    if (dem.resampledFrom)
        m.source.resampled =
            ManifestResampling{dem.resampledFrom->method,   dem.resampledFrom->width,
                               dem.resampledFrom->height,   dem.resampledFrom->geoTransform,
                               totals.originalValidSamples, totals.originalFinestDistance};
    m.quantization = totals.quantization;
    m.build.tool = "terrain-build";
    m.build.version = TERRAIN_VERSION;
    m.build.seconds = totals.seconds;

    // Coverage is the source's own: a rotated grid's resampling is partly empty by shape.
    const auto& resampled = m.source.resampled;
    const std::int64_t samples =
        resampled ? resampled->width * resampled->height : dem.width * dem.height;
    const std::int64_t valid = resampled ? resampled->validSamples : m.statistics.validSamples;
    if (Status empty = refuseEmptySource(dem.path, samples, valid); !empty) return empty.error();
    if (auto warning = mostlyNoDataWarning(dem.path, samples, valid))
        summary.warnings.push_back(*warning);
    summary.patches = totals.patches;
    summary.phases = totals.phases;
    summary.seconds = totals.seconds;
    if (auto written = writeManifest(folder, m); !written) return written.error();
    summary.bytes = folderBytes(folder);
    return summary;
}

}  // namespace detail

Result<PyramidBuildSummary> buildPyramid(DemReader& reader, const fs::path& output,
                                         const PyramidBuildOptions& options) {
    const auto start = Clock::now();
    const DemInfo& dem = reader.info();
    if (Status delta = checkMaxErrorM(output, options.maxErrorM); !delta) return delta.error();
    // Its own samples are placed by a CRS transform, which the planar bounds do not follow.
    if (dem.resampledFrom && !dem.resampledFrom->fromCrs.empty())
        return Error{dem.path +
                     ": reprojected onto a longitude/latitude grid, which only a globe pyramid "
                     "takes; build a planar pyramid from it in its own CRS"};
    auto layout = PyramidLayout::create(dem.width, dem.height, options.patchSamples,
                                        options.blockQuads, options.shardPatches);
    if (!layout) return Error{dem.path + ": " + layout.error().message};
    const PyramidLayout& l = layout.value();

    // The band of the finest level dominates memory. Where one across the whole width
    // exceeds the budget, the same passes run shard by shard (one shard's band at a time).
    const std::uint64_t neededBytes = detail::planarBandBytes(l, l.patchesX(l.finestLevel()));
    if (neededBytes > options.memoryBudgetBytes && !dem.resampledFrom) {
        auto built = buildPyramidByShards(reader, output, options);
        if (built)
            built.value().warnings.insert(
                built.value().warnings.begin(),
                fmt::format("{}: {} samples wide: built shard by shard, since a band across the "
                            "whole width needs about {} MiB, more than --memory ({} MiB)",
                            dem.path, dem.width, neededBytes >> 20,
                            options.memoryBudgetBytes >> 20));
        return built;
    }
    if (neededBytes > options.memoryBudgetBytes)
        return Error{fmt::format(
            "{}: {} samples wide: a band of two patch rows needs about {} MiB, more than the "
            "memory budget of {} MiB (raise --memory; a rotated source is not built shard by "
            "shard yet)",
            dem.path, dem.width, neededBytes >> 20, options.memoryBudgetBytes >> 20)};

    Result<PartialBuildFolder> created = PartialBuildFolder::create(output, options.overwrite);
    if (!created) return created.error();
    PartialBuildFolder& partial = created.value();

    detail::LevelBuilder builder(reader, l, options, partial.path(), detail::planarMaskStored(dem));
    if (auto built = builder.run(); !built) return built.error();

    detail::PlanarBuildTotals totals;
    totals.statistics = builder.statistics();
    totals.levelMaxError = builder.levelMaxError();
    totals.patches = builder.patches();
    totals.originalValidSamples = builder.originalValidSamples();
    totals.originalFinestDistance = builder.originalFinestDistance();
    totals.quantization = builder.quantization();
    totals.phases = builder.phases();
    totals.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    auto summary = detail::finishPlanarBuild(reader, l, totals, partial.path());
    if (!summary) return summary.error();
    if (Status committed = partial.commit(); !committed) return committed.error();
    return summary;
}

}  // namespace terrain::io
