// The streaming pyramid build (LevelBuilder.h): one pass per level, finest first, each in
// bands of two patch rows across the level's full width.
#include "terrain/build/PyramidBuilder.h"

#include "BuildClock.h"
#include "BuildFinish.h"
#include "BuildOutput.h"
#include "LevelBuilder.h"
#include "PlanarManifest.h"
#include "WholeBuilds.h"

#include <fmt/core.h>

#include <chrono>

namespace terrain::io {

namespace fs = std::filesystem;

namespace detail {

bool planarMaskStored(const DemInfo& dem) {
    // The mask is stored when the source declares a no-data value. NaN samples of a float
    // source that declares none are filled and counted all the same, but not masked: the
    // mask costs 2 bytes a sample (half) in every tile, and the build streams, so it has to
    // decide before it has seen the samples.
    // A resampled source is masked too: the resampled grid's corners outside it are no-data.
    return dem.noDataValue.has_value() || dem.resampledFrom.has_value();
}

Result<PyramidManifest> planarManifest(DemReader& reader, const PyramidLayout& layout,
                                       const DemStatistics& stats,
                                       const std::vector<double>& levelMaxError,
                                       const std::optional<ManifestQuantization>& quantization,
                                       const OriginalSamples& original,
                                       std::vector<std::string>& warnings) {
    const DemInfo& dem = reader.info();
    PyramidManifest m = PyramidManifest::forLayout(layout);
    DemReader* const readers[] = {&reader};
    describeSources(m, readers);
    m.noData.present = planarMaskStored(dem);
    m.noData.samples = stats.noDataSamples;
    if (stats.noDataSamples > 0) {  // nothing filled: the manifest of versions before
        m.noData.fill = ManifestNoData::kMembraneFill;
        m.noData.sources.push_back({dem.path, dem.noDataValue, true, stats.noDataSamples, 0});
    }
    m.statistics.minHeight = stats.validSamples > 0 ? stats.minHeight : 0.0;
    m.statistics.maxHeight = stats.validSamples > 0 ? stats.maxHeight : 0.0;
    m.statistics.validSamples = stats.validSamples;
    m.statistics.rootError = levelMaxError.at(0);  // the one root patch's Err(P)
    for (ManifestLevel& level : m.levels)
        level.maxError = levelMaxError.at(static_cast<std::size_t>(level.level));
    if (dem.resampledFrom)
        m.source.resampled = ManifestResampling{
            dem.resampledFrom->method,       dem.resampledFrom->width, dem.resampledFrom->height,
            dem.resampledFrom->geoTransform, original.validSamples,    original.finestDistance};
    m.quantization = quantization;

    // Coverage is the source's own: a rotated grid's resampling is partly empty by shape.
    const auto& resampled = m.source.resampled;
    const std::int64_t samples =
        resampled ? resampled->width * resampled->height : dem.width * dem.height;
    const std::int64_t valid = resampled ? resampled->validSamples : m.statistics.validSamples;
    if (Status covered = checkCoverage(dem.path, samples, valid, warnings); !covered)
        return covered.error();
    return m;
}

// The band of the finest level dominates memory: decideBuildWay (BuildBudget.h) sends a
// raster too wide for the budget shard by shard.
Result<PyramidBuildSummary> buildWholePlanarPyramid(DemReader& reader, const fs::path& output,
                                                    const PyramidBuildOptions& options) {
    const auto start = BuildClock::now();
    const DemInfo& dem = reader.info();
    auto layout = PyramidLayout::create(dem.width, dem.height, options.patchSamples,
                                        options.blockQuads, options.shardPatches);
    if (!layout) return Error{dem.path + ": " + layout.error().message};
    const PyramidLayout& l = layout.value();

    Result<PartialBuildFolder> created = PartialBuildFolder::create(output, options.overwrite);
    if (!created) return created.error();
    PartialBuildFolder& partial = created.value();

    SourceVoids voids(reader);
    LevelBuilder builder(reader, voids, l, options, partial.path(), planarMaskStored(dem));
    if (auto built = builder.run(); !built) return built.error();

    BuildTotals totals{builder.patches(), builder.phases(), secondsSince(start), {}};
    const std::vector<double> levelMaxError(builder.levelMaxError().begin(),
                                            builder.levelMaxError().end());
    auto manifest = planarManifest(
        reader, l, builder.statistics(), levelMaxError, builder.quantization(),
        {builder.originalValidSamples(), builder.originalFinestDistance()}, totals.warnings);
    if (!manifest) return manifest.error();
    auto summary = finishBuild(std::move(manifest).value(), std::move(totals), partial.path());
    if (!summary) return summary.error();
    if (Status committed = partial.commit(); !committed) return committed.error();
    return summary;
}

}  // namespace detail

Result<PyramidBuildSummary> buildPyramid(DemReader& reader, const fs::path& output,
                                         const PyramidBuildOptions& options) {
    DemReader* const readers[] = {&reader};
    return buildPyramid(PyramidSurface::Plane, readers, output, options);
}

}  // namespace terrain::io
