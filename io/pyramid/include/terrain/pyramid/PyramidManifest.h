// PyramidManifest: the pyramid's manifest.json (docs/pyramid-format.md, "manifest.json"):
// format version, layout, georeference, no-data, statistics, levels, source and build.
// A folder is a pyramid exactly when it holds a manifest that reads back without error.
// Every function here is pure or touches only its own file: any thread.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"
#include "terrain/source/Georeference.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace terrain::remote {
class RemoteFiles;
}

namespace terrain::io {

/// One source's no-data: the value it declared and its filled samples (docs/pyramid-format.md,
/// "No-data"). A globe composite's sources each declare their own (a global grid's
/// −9.99e33, SRTM's −32768), so the pyramid's one noData.sourceValue cannot say it.
struct ManifestSourceNoData {
    std::string input;  ///< as in source.inputs
    /// The raw value the source declared as no-data, if any; meaningful when
    /// sourceValueRecorded (manifests before it was recorded per source, read back, know it
    /// only for a pyramid of one source: noData.sourceValue).
    std::optional<double> sourceValue;
    bool sourceValueRecorded = false;
    std::int64_t samples = 0;      ///< its no-data samples, filled
    std::int64_t overBeneath = 0;  ///< of them, filled over the sources beneath it
    bool operator==(const ManifestSourceNoData&) const = default;
};

struct ManifestNoData {
    /// The fill rules: along the row (what versions before the void fill wrote, and what a
    /// pyramid with nothing filled still says); every void by the membrane from its rim;
    /// each void over the sources beneath it (the delta surface), else by the membrane.
    static constexpr std::string_view kRowLinearFill = "row-linear";
    static constexpr std::string_view kMembraneFill = "membrane";
    static constexpr std::string_view kDeltaSurfaceFill = "delta-surface";

    bool present = false;  ///< some source sample was no-data; shards carry the V mask
    /// The raw value the (first) source declared, if any; each source's is in `sources`.
    std::optional<double> sourceValue;
    std::int64_t samples = 0;          ///< filled samples of the DEM (not overhang)
    std::string fill{kRowLinearFill};  ///< the fill rule
    /// Every source of a globe composite; else the one source when it had a sample filled
    /// (absent from the file when it had none, as before the void fill).
    std::vector<ManifestSourceNoData> sources;
    bool operator==(const ManifestNoData&) const = default;
};

/// Over the DEM's valid samples (filled and overhanging samples excluded).
struct ManifestStatistics {
    double minHeight = 0.0;  ///< metres; 0 when there is no valid sample
    double maxHeight = 0.0;
    std::int64_t validSamples = 0;
    double rootError = 0.0;  ///< Err(P) of the root patch, metres
    bool operator==(const ManifestStatistics&) const = default;
};

struct ManifestLevel {
    int level = 0;
    std::int64_t patchesX = 0;
    std::int64_t patchesY = 0;
    std::int64_t presentPatches = 0;
    std::int64_t shardsX = 0;
    std::int64_t shardsY = 0;
    std::int64_t sampleStep = 1;  ///< DEM samples between two samples of the level
    double maxError = 0.0;        ///< largest Err(P) of the level's patches, metres
    /// Globe pyramids only (sparse): the shards (sx, sy) that exist; every other shard of the
    /// level holds absent patches only and has no file. Sorted by (sy, sx).
    std::vector<ShardId> presentShards;
    bool operator==(const ManifestLevel&) const = default;
};

/// Where a finer source of a globe pyramid is blended into a coarser one at its edges
/// (docs/pyramid-format.md, "Globe pyramids"; docs/globe.md, "How it works"): the largest slope
/// the blend adds (the step between the two times the weight's slope) against the source's own
/// 99th-percentile slope, which it should stay within.
struct ManifestSeam {
    std::string input;            ///< as in source.inputs
    double seamSlope = 0.0;       ///< metres per metre
    double sourceSlopeP99 = 0.0;  ///< metres per metre
    /// The largest ratio of the slope the blend adds to the source's 99th-percentile slope
    /// over a baseline as wide as the band there (what the band is fitted to): ≤ 1 but where
    /// capped.
    double bandScaleRatio = 0.0;
    double largestStepM = 0.0;           ///< the largest height step across the band
    std::array<double, 2> bandPixels{};  ///< the band's narrowest and widest, source pixels
    std::array<double, 2> bandMetres{};  ///< the same, metres
    /// Pixels along the edges where the band reached its widest (a quarter of the source)
    /// short of the width the step needed.
    std::int64_t cappedPixels = 0;
    bool operator==(const ManifestSeam&) const = default;
};

/// One source of a globe pyramid and where it lies (docs/pyramid-format.md, "Globe pyramids"):
/// what the default flight visits (a composite's sourceExtent is its finest source's only).
struct ManifestGlobeSource {
    std::string input;  ///< as in source.inputs
    /// Its extent, degrees, as sourceExtent (west may exceed east across the antimeridian; a
    /// source around the whole Earth is −180 … 180).
    double west = -180.0, south = -90.0, east = 180.0, north = 90.0;
    /// Its native grid (terrain-build --native-leaves; optional in the file, empty: none):
    /// the folder, relative to the pyramid, of a planar pyramid of its own samples as the
    /// composite shows them, on its own longitude/latitude grid grown by a margin
    /// (docs/globe.md, "Native leaves"). Always kNativeFolder followed by a number.
    std::string native;
    static constexpr std::string_view kNativeFolder = "native/";
    bool operator==(const ManifestGlobeSource&) const = default;
};

/// A globe pyramid's tiling (format version 3, docs/pyramid-format.md, "Globe pyramids"):
/// the six cube faces of terrain::globe side by side in one layout. Face level l of face f
/// is layout level l + kLevelOffset, its patch (x, y) the layout patch (f · 2^l + x, y).
struct ManifestGlobe {
    static constexpr std::string_view kTiling = "wgs84-tangent-cube";
    /// Layout levels above the faces: the layout is 6 faces wide, so its levels 0 to 2
    /// (1, 2 and 3 patches wide) would mix faces; they hold no patch.
    static constexpr int kLevelOffset = 3;
    int faceFinestLevel = 0;  ///< L: face levels 0 … L
    /// The source's extent, degrees (west may exceed east across the antimeridian): where
    /// "go to the data" goes.
    double west = -180.0, south = -90.0, east = 180.0, north = 90.0;
    /// One per source blended into a coarser one (optional in the file: absent before the
    /// band followed the step, and where no source lies over another).
    std::vector<ManifestSeam> seams;
    /// Every source, finest first (optional in the file: absent before it was recorded; a
    /// reader then knows the finest source's extent only).
    std::vector<ManifestGlobeSource> sources;
    /// The height of the sea in the sources' vertical datum, metres (optional in the file,
    /// 0: mean sea level, as SRTM and ETOPO state it): what lies at or below it is drawn as
    /// water. A source whose zero is not the sea (heights above the ellipsoid, a lake's
    /// surface) states its own (terrain-build --sea-level).
    double seaLevelM = 0.0;
    /// Face levels built below each source's own spacing (terrain-build --oversample-levels;
    /// optional in the file, 0): each source's finest face level is that many finer than its
    /// samples, so the finest level's resampling error against them is smaller.
    int oversampleLevels = 0;
    bool operator==(const ManifestGlobe&) const = default;
};

/// A rotated or sheared source resampled onto the pyramid's grid (DemInfo::resampledFrom).
struct ManifestResampling {
    std::string method;                    ///< "bilinear"
    std::int64_t width = 0, height = 0;    ///< the source's own samples
    std::array<double, 6> geoTransform{};  ///< the source's, in GDAL's order
    std::int64_t validSamples = 0;         ///< of the source's own samples
    /// The largest distance of a source sample from the finest level's surface: what the
    /// resampling alone costs; every level's Err(P) covers the source's samples.
    double finestDistanceM = 0.0;
    bool operator==(const ManifestResampling&) const = default;
};

struct ManifestSource {
    std::vector<std::string> inputs;
    std::string reader;      ///< DemInfo::readerName
    std::string sampleType;  ///< DemInfo::sampleType
    /// DemInfo::band of bandCount, and whether rows or columns were flipped on read
    /// (optional in the file: a manifest without them read band 1 of 1, north-up).
    int band = 1;
    int bandCount = 1;
    bool rowsFlipped = false;
    bool columnsFlipped = false;
    std::optional<ManifestResampling> resampled{};  ///< optional in the file
    bool operator==(const ManifestSource&) const = default;
};

/// A lossy pyramid's quantizer (terrain-build --max-error-m; Yusov & Shevtsov 2011, §4):
/// level l's heights are whole multiples of 2δ_l, δ_l = maxErrorM · 2^(finestLevel − l),
/// each within δ_l of the source's sample (up to half a float ulp, which the patches'
/// quantError counts).
struct ManifestQuantization {
    static constexpr std::string_view kRule = "yusov2011";  ///< δ_l doubles per coarser level
    double maxErrorM = 0.0;  ///< δ of the finest level, metres (> 0)
    /// The largest |stored − source| over the finest level's samples, metres (≤ maxErrorM
    /// up to float rounding).
    double finestLargestErrorM = 0.0;
    /// δ_l.
    double halfStep(int level, int finestLevel) const;
    /// 2δ_l: what level l's heights are whole multiples of (HeightUnits::quantizerStep).
    double step(int level, int finestLevel) const { return 2.0 * halfStep(level, finestLevel); }
    bool operator==(const ManifestQuantization&) const = default;
};

/// One imagery layer draped on the terrain (issue 47, docs/imagery.md): its tiles lie on the
/// pyramid's own tiling (ImageryTile.h). Layers are drawn in the manifest's order, each later
/// one composited over those before it by its alpha times its opacity.
struct ManifestImageryLayer {
    /// Tiles stored in the layer's folder ("tiles"), or generated where they are read: the
    /// virtual planet's colours from its heights ("planet").
    static constexpr std::string_view kStoredKind = "tiles";
    static constexpr std::string_view kPlanetKind = "planet";
    std::string name;    ///< unique within the pyramid; what the tools and the viewer show
    std::string kind{kStoredKind};
    std::string folder;  ///< relative to the pyramid folder ("imagery/<name>"); "" for "planet"
    std::string input;   ///< the image it was built from, as given ("" for "planet")
    std::string codec;   ///< how tiles are stored ("webp"; "" for "planet")
    /// Layout levels of its tiles: coarsestLevel … finestLevel (finestLevel may exceed the
    /// pyramid's finest: imagery finer than the DEM). coarsestLevel is the pyramid's root
    /// level (0; ManifestGlobe::kLevelOffset on the globe).
    int coarsestLevel = 0;
    int finestLevel = 0;
    double opacity = 1.0;  ///< 0 … 1, times each texel's alpha
    bool operator==(const ManifestImageryLayer&) const = default;
};

struct ManifestBuild {
    std::string tool;
    std::string version;
    double seconds = 0.0;
    bool operator==(const ManifestBuild&) const = default;
};

struct PyramidManifest {
    static constexpr std::string_view kFormatName = "terrain-pyramid";
    /// Planar pyramids. Version 8 stores each patch as one zstd payload whose heights may be
    /// predicted from the parent patch's (shard format 4); 6 had payloads without that
    /// (format 3); 4 stored height codes in ZIP parts (and 5 was the globe's), 2 and 3
    /// floats; 1 had weaker block errors.
    static constexpr int kFormatVersion = 8;
    /// Globe pyramids (`globe` is set): version 9, with the shards of version 8 (their
    /// patches predicted within themselves); 7 and 5 had those of versions 6 and 4.
    static constexpr int kGlobeFormatVersion = 9;
    static constexpr std::string_view kFileName = "manifest.json";
    static constexpr std::string_view kVerticalUnits = "metre";

    int formatVersion = kFormatVersion;
    /// patchSamples, blockQuads, shardPatches, raster size, finestLevel (apronSamples is
    /// always 1). fromJson builds it with PyramidLayout::create, so it is always valid
    /// in a manifest that was read; writeManifest checks it again.
    PyramidLayout layout;
    Georeference georeference;   ///< crsKind, epsg, wkt, origin and pixel size
    VerticalTransform vertical;  ///< stored metres = source · scale + offset
    ManifestNoData noData;
    ManifestStatistics statistics;
    std::vector<ManifestLevel> levels;  ///< one per level, root first
    ManifestSource source;
    ManifestBuild build;
    /// Set exactly for a globe pyramid (formatVersion 3); the georeference is then the
    /// source's (geographic), and the layout is globeLayout(globe->faceFinestLevel, …).
    std::optional<ManifestGlobe> globe;
    /// Set for a lossy pyramid (optional in the file).
    std::optional<ManifestQuantization> quantization;
    /// Imagery layers, bottom first (optional in the file: absent, none).
    std::vector<ManifestImageryLayer> imagery;

    /// A manifest for `layout`: the layout and one level entry per level (patch and shard
    /// counts, sample step; presentPatches = all patches, maxError = 0), the rest default.
    /// The builder fills in the rest.
    static PyramidManifest forLayout(const PyramidLayout& layout);

    bool operator==(const PyramidManifest&) const = default;
};

/// The manifest as JSON text (keys in the order of the spec, 2-space indent). Doubles are
/// written with enough digits to read back bit for bit.
std::string toJson(const PyramidManifest& manifest);

/// Parses and checks manifest JSON: format name, a supported formatVersion, every field
/// present with the right type, a layout PyramidLayout::create accepts, and finestLevel
/// and levels that match it. Errors start with `sourceName` (the file, for messages).
Result<PyramidManifest> fromJson(std::string_view json, const std::string& sourceName);

/// Checks `manifest` as fromJson would, then writes `<pyramidDir>/manifest.json` through
/// an AtomicFile. The folder must exist.
Status writeManifest(const std::filesystem::path& pyramidDir, const PyramidManifest& manifest);

/// Reads `<pyramidDir>/manifest.json`. A folder without one is "not a pyramid". The virtual
/// planet's name ("planet:…", VirtualPlanetPyramid.h) gives its manifest instead.
Result<PyramidManifest> readManifest(const std::filesystem::path& pyramidDir);
/// readManifest for a pyramid at a URL through a reader's own `files` (non-null for a URL,
/// ignored for a folder), so that opening a pyramid checks its manifest with the server once.
Result<PyramidManifest> readManifest(const std::filesystem::path& pyramidDir,
                                     remote::RemoteFiles* files);

}  // namespace terrain::io
