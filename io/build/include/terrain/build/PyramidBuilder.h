// PyramidBuilder: turns a DEM of any size into the on-disk pyramid
// (docs/pyramid-format.md), streaming: it holds a band of two patch rows of one level at
// a time, never the raster, and computes every patch's error bounds on the way
// (Yusov & Shevtsov 2011, §4 and §5).
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/ShardWriter.h"

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>

namespace terrain::io {

struct PyramidBuildProgress {
    int level = 0;          ///< level being written
    double fraction = 0.0;  ///< of the whole build, by samples
};

/// The most face levels a globe build adds below a source's spacing: each multiplies the
/// finest level's samples by 4.
inline constexpr int kMaxGlobeOversampleLevels = 3;

struct PyramidBuildOptions {
    int patchSamples = PyramidLayout::kDefaultPatchSamples;
    int blockQuads = PyramidLayout::kDefaultBlockQuads;
    int shardPatches = PyramidLayout::kDefaultShardPatches;
    std::uint64_t memoryBudgetBytes = std::uint64_t{1} << 30;
    unsigned threads = 0;  ///< 0: one per hardware thread
    /// zstd level of the patch payloads, 0 (stored uncompressed) … 19; lossless at every
    /// level. The heights are stored as height codes (HeightCodes.h), small integers that
    /// zstd shrinks several times over (docs/pyramid-format.md, "Compression"); 0 stores
    /// them as large as floats.
    int compressionLevel = ShardWriterOptions::kDefaultCompressionLevel;
    /// δ > 0: lossy storage (Yusov & Shevtsov 2011, §4). The finest level's heights are
    /// rounded to whole multiples of 2δ, level l's to 2δ_l with δ_l = δ · 2^(finest − l);
    /// every stored sample stays within δ_l of the source and Err(P) = Err_Appr(P) + δ_l,
    /// so the screen-space bound still holds. 0: lossless.
    double maxErrorM = 0.0;
    /// Below the root, code each patch's heights from its parent's where that is smaller
    /// (docs/pyramid-format.md, "Height codes"); false makes every patch decodable on its
    /// own, at 10–20 % more bytes (a server handing out single patches). Planar pyramids.
    bool parentPrediction = true;
    /// A globe region build (PyramidShards.h): the levels above the finest whose Err(P) is
    /// measured at the source's samples before the nested bound takes over; −1 is 2, and every
    /// level of a shard whose surroundings hold at most 2^24 samples.
    int globeMeasuredLevels = -1;
    /// A globe pyramid's sea level in its sources' vertical datum, metres
    /// (ManifestGlobe::seaLevelM).
    double globeSeaLevelM = 0.0;
    /// Globe pyramids: face levels built below each source's own spacing
    /// (ManifestGlobe::oversampleLevels). A face grid resamples a source, and the finest
    /// level's distance from the source's own triangles (its Err(P)) is the floor of the error
    /// a user sees near the ground; each level roughly halves it for 4 × the finest level's
    /// samples (docs/globe.md, "Oversampled finest levels"). 0 … kMaxGlobeOversampleLevels.
    int globeOversampleLevels = 0;
    /// Globe pyramids: also write each longitude/latitude source's own samples, as the
    /// composite shows them, as a planar pyramid on its own grid (ManifestGlobeSource::native;
    /// docs/globe.md, "Native leaves"): the data a finest face patch is drawn from at the
    /// sources' own samples. Whole builds only.
    bool globeNativeLeaves = false;
    /// Planar whole builds: the least Err_Appr(P) of the finest level's patch (x, y), when
    /// the pyramid's truth is wider than its raster (a native grid's: the samples of the other
    /// sources the composite shows on it, NativeGrids.h); every coarser level's bound nests
    /// over it. Empty: 0.
    std::function<float(std::int64_t x, std::int64_t y)> finestErrorFloor;
    bool overwrite = false;  ///< replace an existing pyramid at the output path
    /// Called on the building thread after every band.
    std::function<void(const PyramidBuildProgress&)> progress;
    /// Polled between bands; when it becomes true the build stops, removes its partial
    /// output and returns an Error.
    const std::atomic<bool>* cancel = nullptr;
};

/// Where the time went, summed over all levels (seconds of the building thread).
struct PyramidBuildPhases {
    double readSeconds = 0.0;    ///< source reads and no-data fill (or level rasters)
    double boundsSeconds = 0.0;  ///< min/max, λ(d), Err_Int, coarser level rasters
    double writeSeconds = 0.0;   ///< tile compression and shard files
};

struct PyramidBuildSummary {
    PyramidManifest manifest;
    std::int64_t patches = 0;
    std::uint64_t bytes = 0;  ///< shard files and manifest on disk
    double seconds = 0.0;
    PyramidBuildPhases phases;
    /// What the user should know about the sources (most of a source is no-data), each
    /// naming the file.
    std::vector<std::string> warnings;
};

/// The surface a pyramid lies on: a plane (the source's own grid, format versions 1–2) or
/// the WGS84 cube-sphere (format version 3, GlobePyramidBuilder.h).
enum class PyramidSurface { Plane, Globe };

/// How a build runs: whole where what it holds fits options.memoryBudgetBytes and shard by
/// shard where not (Automatic; a source that cannot be built by shards is refused then),
/// or shard by shard in any case (ByShards, PyramidShards.h), or whole in any case (Whole).
enum class BuildWay { Automatic, Whole, ByShards };

/// Builds the pyramid of `readers` on `surface` at `output` (a folder): on a plane one
/// source (a mosaic is one reader); on the globe one or several, composited. The folder is
/// built as "<output>.partial-<pid>" (by shards: "<output>.parts") and renamed into place
/// only when complete, so an interrupted or failed build never leaves a valid-looking
/// pyramid. A build the budget sends shard by shard says so in its warnings. Errors name the
/// file and the problem; a source without a valid sample is one. Calling thread (plus worker
/// threads it owns).
Result<PyramidBuildSummary> buildPyramid(PyramidSurface surface,
                                         std::span<DemReader* const> readers,
                                         const std::filesystem::path& output,
                                         const PyramidBuildOptions& options = {},
                                         BuildWay way = BuildWay::Automatic);

/// The planar pyramid of one source: buildPyramid(PyramidSurface::Plane, {&reader}, …).
Result<PyramidBuildSummary> buildPyramid(DemReader& reader, const std::filesystem::path& output,
                                         const PyramidBuildOptions& options = {});

}  // namespace terrain::io
