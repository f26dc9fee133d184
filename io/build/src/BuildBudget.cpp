#include "BuildBudget.h"

#include "BuildOutput.h"
#include "GeographicGrid.h"
#include "GlobeSources.h"
#include "WholeBuilds.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/PyramidShards.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::io {
namespace detail {

std::string memoryBudgetMessage(std::string_view path, std::string_view what,
                                std::uint64_t neededBytes, std::uint64_t budgetBytes,
                                std::string_view remedy) {
    constexpr std::uint64_t kMiB = std::uint64_t{1} << 20;
    return fmt::format("{}: {} needs about {} MiB, more than --memory ({} MiB); {}", path, what,
                       (neededBytes + kMiB - 1) / kMiB, budgetBytes / kMiB, remedy);
}

Status checkMemoryBudget(std::string_view path, std::string_view what, std::uint64_t neededBytes,
                         std::uint64_t budgetBytes, std::string_view remedy) {
    if (neededBytes <= budgetBytes) return {};
    return Error{memoryBudgetMessage(path, what, neededBytes, budgetBytes, remedy)};
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

}  // namespace detail

Status shardable(PyramidSurface surface, std::span<DemReader* const> readers) {
    if (readers.size() != 1)
        return Error{
            "--plan, --shard, --merge and --by-shards build a globe pyramid of one source; "
            "several are composited whole (give them as one mosaic, or build without a region "
            "option)"};
    const DemInfo& dem = readers.front()->info();
    if (dem.resampledFrom)
        return Error{dem.path + (surface == PyramidSurface::Globe
                                     ? ": a projected or rotated source is not built shard by "
                                       "shard yet; build it whole (--globe without a region "
                                       "option), within --memory"
                                     : ": a rotated or sheared source is not built shard by "
                                       "shard yet (build it whole)")};
    return {};
}

namespace detail {
namespace {

// A whole build that would hold `needed` bytes (`what`, of the source at `path`), over the
// budget: shard by shard with a warning, or, where it cannot go by shards, refused.
Result<BuildDecision> overBudget(std::string_view path, std::string_view what, std::uint64_t needed,
                                 const PyramidBuildOptions& options, const Status& canShard) {
    if (!canShard)
        return Error{memoryBudgetMessage(path, what, needed, options.memoryBudgetBytes,
                                         "raise --memory (" + canShard.error().message + ")")};
    return BuildDecision{
        BuildWay::ByShards,
        memoryBudgetMessage(path, what, needed, options.memoryBudgetBytes, "built shard by shard")};
}

// A planar pyramid's whole build holds a band of two patch rows across the finest level.
Result<BuildDecision> decidePlanar(DemReader& reader, const PyramidBuildOptions& options,
                                   BuildWay requested) {
    const DemInfo& dem = reader.info();
    // Its own samples are placed by a CRS transform, which the planar bounds do not follow.
    if (dem.resampledFrom && !dem.resampledFrom->fromCrs.empty())
        return Error{dem.path +
                     ": reprojected onto a longitude/latitude grid, which only a globe pyramid "
                     "takes; build a planar pyramid from it in its own CRS"};
    DemReader* const readers[] = {&reader};
    const Status canShard = shardable(PyramidSurface::Plane, readers);
    if (requested == BuildWay::ByShards) {
        if (!canShard) return canShard.error();
        return BuildDecision{BuildWay::ByShards, std::nullopt};
    }
    auto layout = PyramidLayout::create(dem.width, dem.height, options.patchSamples,
                                        options.blockQuads, options.shardPatches);
    if (!layout) return Error{dem.path + ": " + layout.error().message};
    const PyramidLayout& l = layout.value();
    const std::uint64_t needed = planarBandBytes(l, l.patchesX(l.finestLevel()));
    const std::string what =
        fmt::format("a band of two patch rows across its {} samples", dem.width);
    if (requested == BuildWay::Whole || needed <= options.memoryBudgetBytes)
        return BuildDecision{BuildWay::Whole, std::nullopt};
    return overBudget(dem.path, what, needed, options, canShard);
}

// What a whole globe build of one geographic source holds at its peak, beyond the process's
// own (about 150 MB): about 40 bytes a source sample (its heights and mask, its place on the
// cube, its measured height) and 9 a sample of the finest face level over its footprint (that
// level's patches, reaching a patch or two past it, resampled, measured and written while all
// are held). Fitted to the peak RSS of whole builds of N57E011 and the Rainier tile at 1201²
// and at 3601² (2 threads; docs/accuracy.md, "What a whole globe build holds"), whose finest
// face levels hold 2.6 to 7.2 samples a source sample. 0 for a source not on a
// longitude/latitude grid (its grid is known once it is read).
std::uint64_t wholeGlobeBuildBytes(const DemInfo& dem, const PyramidBuildOptions& options) {
    const Georeference& g = dem.georeference;
    if (g.crsKind != CrsKind::Geographic) return 0;
    constexpr double kDegree = std::numbers::pi / 180.0;
    const double north = std::clamp(g.originY, -90.0, 90.0);
    const double south = std::clamp(g.originY - double(dem.height) * g.pixelSizeY, -90.0, 90.0);
    const double spanLon = std::min(360.0, double(dem.width) * g.pixelSizeX);
    const bool wraps = spanLon >= 360.0;
    const int quads = options.patchSamples - 1;
    const int level =
        finestFaceLevelOf(south, north, g.originX, g.originX + spanLon, wraps,
                          geographicFinestSpacingMetres(south, north, g.pixelSizeX, g.pixelSizeY),
                          quads, options.globeOversampleLevels);
    const double centreLat = 0.5 * (north + south);
    const double centreLon = wraps ? 0.0 : g.originX + 0.5 * spanLon;
    const double faceSpacing = globeFaceSampleSpacing(level, centreLat, centreLon, quads);
    constexpr double kMeanRadius = 6371008.8;
    const double area = kMeanRadius * kMeanRadius * spanLon * kDegree *
                        std::abs(std::sin(north * kDegree) - std::sin(south * kDegree));
    const double faceSamples = area / (faceSpacing * faceSpacing);
    return static_cast<std::uint64_t>(40.0 * double(dem.width) * double(dem.height) +
                                      9.0 * faceSamples);
}

// A globe pyramid's whole build holds its sources whole (GlobeSources::read also checks
// their samples against half the budget); one geographic source whose whole build would hold
// more than the budget (wholeGlobeBuildBytes) is built shard by shard, in memory bounded
// whatever its size. What cannot go by shards (sources composited together, a projected one)
// is refused over the budget, as a planar build is, unless asked for whole.
Result<BuildDecision> decideGlobe(std::span<DemReader* const> readers,
                                  const std::filesystem::path& output,
                                  const PyramidBuildOptions& options, BuildWay requested) {
    if (readers.empty())
        return Error{output.string() + ": no source to build a globe pyramid from"};
    const Status canShard = shardable(PyramidSurface::Globe, readers);
    if (requested == BuildWay::ByShards) {
        if (!canShard) return canShard.error();
        return BuildDecision{BuildWay::ByShards, std::nullopt};
    }
    std::uint64_t held = 0;
    for (DemReader* reader : readers) held += wholeGlobeBuildBytes(reader->info(), options);
    if (requested == BuildWay::Whole || held <= options.memoryBudgetBytes)
        return BuildDecision{BuildWay::Whole, std::nullopt};
    const DemInfo& first = readers.front()->info();
    const std::string what =
        readers.size() == 1
            ? fmt::format("a whole globe build of its {} × {} samples", first.width, first.height)
            : fmt::format("a whole globe build of its {} sources", readers.size());
    return overBudget(first.path, what, held, options, canShard);
}

}  // namespace

Result<BuildDecision> decideBuildWay(PyramidSurface surface, std::span<DemReader* const> readers,
                                     const std::filesystem::path& output,
                                     const PyramidBuildOptions& options, BuildWay requested) {
    if (Status delta = checkMaxErrorM(output, options.maxErrorM); !delta) return delta.error();
    if (surface == PyramidSurface::Globe) return decideGlobe(readers, output, options, requested);
    TERRAIN_ASSERT(readers.size() == 1, "a planar pyramid is built from one source (a mosaic)");
    return decidePlanar(*readers.front(), options, requested);
}

}  // namespace detail

Result<PyramidBuildSummary> buildPyramid(PyramidSurface surface,
                                         std::span<DemReader* const> readers,
                                         const std::filesystem::path& output,
                                         const PyramidBuildOptions& options, BuildWay way) {
    auto decided = detail::decideBuildWay(surface, readers, output, options, way);
    if (!decided) return decided.error();
    const bool globe = surface == PyramidSurface::Globe;
    if (options.globeNativeLeaves && !globe)
        return Error{fmt::format(
            "{}: native leaves (--native-leaves) are for globe pyramids: a planar pyramid's "
            "finest level is already the source's own grid",
            readers.front()->info().path)};
    Result<PyramidBuildSummary> built =
        decided.value().way == BuildWay::Whole
            ? (globe ? detail::buildWholeGlobePyramid(readers, output, options)
                     : detail::buildWholePlanarPyramid(*readers.front(), output, options))
            : buildPyramidByShards(surface, *readers.front(), output, options);
    if (built && decided.value().warning)
        built.value().warnings.insert(built.value().warnings.begin(), *decided.value().warning);
    return built;
}

}  // namespace terrain::io
