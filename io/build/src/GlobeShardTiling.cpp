// The globe's shard tiling (ShardTiling.h, PyramidShards.h): which shards of the cube-sphere
// reach one geographic source, a finest shard built from the source's samples around it read
// block by block, a coarser one from its children's carries, measured at the source's samples
// or, above the measured levels, bounded by the nested bound (carryToParents).
#include "ShardTiling.h"

#include "BuildClock.h"
#include "GeographicBlocks.h"
#include "GeographicGrid.h"
#include "GlobePatchBuild.h"
#include "GlobeSources.h"
#include "NativeGrids.h"
#include "ParallelFor.h"
#include "RegionStaging.h"
#include "terrain/build/GlobePatchSurface.h"
#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/pyramid/PatchErrors.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <set>
#include <thread>
#include <unordered_map>
#include <unordered_set>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;
using detail::idOf;
using detail::keyOf;
using detail::patchIndex;
using detail::PatchKey;
using globe::GlobePatchId;

constexpr int kOffset = ManifestGlobe::kLevelOffset;
// Patches of the finest level around a shard whose source samples it reads: a sample makes
// patches up to two neighbours away exist (detail::addPatchesAround); one more covers the
// other faces' patches, whose face coordinates run at another rate across a cube edge.
constexpr double kMarginPatches = 3.0;

// What decides the shards' bytes: the source as read (and where its grid lies), the build
// options, and how a global grid meets a pole ("fan": GeographicGrid's pole height; before it,
// clamped rows), so that a staging folder half built by an older terrain-build is refused,
// not finished with shards of another surface.
std::string globeFingerprint(const DemInfo& dem, const PyramidLayout& layout,
                             const PyramidBuildOptions& options) {
    const Georeference& g = dem.georeference;
    return detail::regionFingerprint(dem, layout, options,
                                     {{"tiling", "globe"},
                                      {"formatVersion", PyramidManifest::kGlobeFormatVersion},
                                      {"grid", {g.originX, g.originY, g.pixelSizeX, g.pixelSizeY}},
                                      {"measuredLevels", options.globeMeasuredLevels},
                                      {"oversampleLevels", options.globeOversampleLevels},
                                      {"poles", "fan"}});
}

// ---------------------------------------------------------------------------------------
// Where a shard lies on the globe.

// A shard's patches on one face: [x0, x1) × [y0, y1) of its face level.
struct FaceRect {
    int face = 0;
    std::int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

std::vector<FaceRect> faceRectsOf(const PyramidLayout& layout, const ShardId& s) {
    const std::int64_t n = globe::patchesPerFaceSide(s.level - kOffset);
    const std::int64_t x0 = layout.shardFirstX(s), y0 = layout.shardFirstY(s);
    const std::int64_t x1 = x0 + layout.shardCountX(s), y1 = y0 + layout.shardCountY(s);
    std::vector<FaceRect> rects;
    for (int face = 0; face < globe::kCubeFaces; ++face) {
        const std::int64_t a = std::max(x0, face * n) - face * n;
        const std::int64_t b = std::min(x1, (face + 1) * n) - face * n;
        if (a < b && y0 < std::min(y1, n)) rects.push_back({face, a, y0, b, std::min(y1, n)});
    }
    return rects;
}

// A conservative longitude/latitude box: every direction of the region lies inside.
struct LonLatBox {
    double south = -90.0, north = 90.0, west = -180.0, east = 180.0;
    bool allLongitudes = true;
};

double wrapDegrees(double d) {
    d = std::fmod(d + 180.0, 360.0);
    if (d < 0.0) d += 360.0;
    return d - 180.0;
}

// The box of a face rectangle of `level` grown by `margin` patches on every side, from points
// along its boundary (longitudes unwound along it), grown by the largest step between them so
// the boundary's bulge between points stays inside; a region holding a pole, or close to one,
// spans every longitude.
LonLatBox boxOf(const FaceRect& r, int level, double margin) {
    const double n = double(globe::patchesPerFaceSide(level));
    const double s0 = (double(r.x0) - margin) / n, s1 = (double(r.x1) + margin) / n;
    const double t0 = (double(r.y0) - margin) / n, t1 = (double(r.y1) + margin) / n;
    // Beyond about half a face the face's own coordinates no longer reach (the tangent
    // adjustment runs out at −0.5 and 1.5): the whole globe.
    if (s0 < -0.4 || t0 < -0.4 || s1 > 1.4 || t1 > 1.4) return {};
    constexpr int kPerSide = 16;
    std::vector<globe::Geodetic> loop;
    loop.reserve(4 * kPerSide);
    const auto add = [&](double s, double t) {
        loop.push_back(globe::Wgs84::geodeticOfNormal(globe::directionOf(r.face, s, t)));
    };
    for (int k = 0; k < kPerSide; ++k) add(s0 + (s1 - s0) * k / kPerSide, t0);
    for (int k = 0; k < kPerSide; ++k) add(s1, t0 + (t1 - t0) * k / kPerSide);
    for (int k = 0; k < kPerSide; ++k) add(s1 - (s1 - s0) * k / kPerSide, t1);
    for (int k = 0; k < kPerSide; ++k) add(s0, t1 - (t1 - t0) * k / kPerSide);

    LonLatBox box;
    box.south = 90.0;
    box.north = -90.0;
    double step = 0.0;  // the largest angle between neighbouring boundary points, degrees
    double longitude = loop.front().longitudeDeg, west = longitude, east = longitude;
    for (std::size_t k = 0; k < loop.size(); ++k) {
        const globe::Geodetic& p = loop[k];
        const globe::Geodetic& next = loop[(k + 1) % loop.size()];
        box.south = std::min(box.south, p.latitudeDeg);
        box.north = std::max(box.north, p.latitudeDeg);
        const glm::dvec3 a = globe::Wgs84::normalAt(p.latitudeDeg, p.longitudeDeg);
        const glm::dvec3 b = globe::Wgs84::normalAt(next.latitudeDeg, next.longitudeDeg);
        step = std::max(step, std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) / kDegree);
        longitude += wrapDegrees(next.longitudeDeg - p.longitudeDeg);
        west = std::min(west, longitude);
        east = std::max(east, longitude);
    }
    // Back at the start: a loop that wound once around the axis holds a pole.
    const bool holdsPole = std::abs(longitude - loop.front().longitudeDeg) > 180.0;
    const double grow = 2.0 * step + 1e-9;
    box.south = std::max(-90.0, box.south - grow);
    box.north = std::min(90.0, box.north + grow);
    if (holdsPole) {
        if (box.north > 0.0) box.north = 90.0;
        if (box.south < 0.0) box.south = -90.0;
    }
    const double highest = std::max(std::abs(box.south), std::abs(box.north));
    if (holdsPole || highest > 89.0) return box;  // allLongitudes
    const double growLongitude = grow / std::cos(highest * kDegree);
    if (east - west + 2.0 * growLongitude >= 360.0) return box;
    box.allLongitudes = false;
    box.west = west - growLongitude;
    box.east = east + growLongitude;
    return box;
}

// The box around a shard with the finest level's margin; several faces: the whole globe.
LonLatBox boxOfShard(const PyramidLayout& layout, const ShardId& s, int finestFaceLevel) {
    const std::vector<FaceRect> rects = faceRectsOf(layout, s);
    if (rects.size() != 1) return {};
    const int level = s.level - kOffset;
    return boxOf(rects.front(), level, kMarginPatches / std::ldexp(1.0, finestFaceLevel - level));
}

// The source's columns whose samples may lie in a box: one range, or two across the
// longitudes' seam of a grid that does not wrap; all of them for a box of every longitude.
struct ColumnRange {
    std::int64_t first = 0, end = 0;
};

bool reachesSource(const LonLatBox& box, const GeographicGrid& grid) {
    const double pixelLat = grid.pixelLatDeg();
    if (box.south > grid.northDeg() + pixelLat || box.north < grid.southDeg() - pixelLat)
        return false;
    if (box.allLongitudes || grid.wrapsLongitude()) return true;
    const double pixelLon = grid.pixelLonDeg();
    for (const double shift : {-360.0, 0.0, 360.0})
        if (box.west + shift <= grid.eastDeg() + pixelLon &&
            box.east + shift >= grid.westDeg() - pixelLon)
            return true;
    return false;
}

struct SourceWindow {
    std::int64_t row0 = 0, row1 = 0;
    std::vector<ColumnRange> columns;
};

SourceWindow windowOf(const LonLatBox& box, const GeographicGrid& grid) {
    SourceWindow w;
    const double pixelLat = grid.pixelLatDeg();
    const double pixelLon = grid.pixelLonDeg();
    const auto row = [&](double latitude) { return (grid.northDeg() - latitude) / pixelLat - 0.5; };
    w.row0 = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(row(box.north))) - 1, 0,
                                      grid.height());
    w.row1 = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil(row(box.south))) + 2, 0,
                                      grid.height());
    if (w.row0 >= w.row1) return w;
    if (box.allLongitudes) {
        w.columns.push_back({0, grid.width()});
        return w;
    }
    for (const double shift : {-360.0, 0.0, 360.0}) {
        const double first = (box.west + shift - grid.westDeg()) / pixelLon - 0.5;
        const double last = (box.east + shift - grid.westDeg()) / pixelLon - 0.5;
        const auto a = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(first)) - 1, 0,
                                                grid.width());
        const auto b = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil(last)) + 2, 0,
                                                grid.width());
        if (a < b) w.columns.push_back({a, b});
    }
    std::sort(w.columns.begin(), w.columns.end(),
              [](const ColumnRange& x, const ColumnRange& y) { return x.first < y.first; });
    std::vector<ColumnRange> merged;
    for (const ColumnRange& c : w.columns) {
        if (!merged.empty() && c.first <= merged.back().end)
            merged.back().end = std::max(merged.back().end, c.end);
        else
            merged.push_back(c);
    }
    w.columns = std::move(merged);
    return w;
}

// ---------------------------------------------------------------------------------------
// The plan.

struct Source {
    GeographicGrid grid;
    int faceFinestLevel = 0;
};

// The source's grid (shardable has refused a projected or rotated one) and finest face level.
Result<Source> describeSource(DemReader& reader, int quads, int oversampleLevels) {
    Result<GeographicGrid> grid = GeographicGrid::describe(reader.info());
    if (!grid) return grid.error();
    // As GlobeSources::read decides it, so the whole build and the region build agree.
    const int level = finestFaceLevelOf(grid.value(), quads, oversampleLevels);
    return Source{std::move(grid).value(), level};
}

// A source around the whole globe, from pole to pole: every shard's box reaches it.
bool coversTheGlobe(const GeographicGrid& grid) {
    const double pixelLat = grid.pixelLatDeg();
    return grid.wrapsLongitude() && grid.northDeg() >= 90.0 - pixelLat &&
           grid.southDeg() <= -90.0 + pixelLat;
}

// A shard may be built when its box, and every box above it, reaches the source: the plan's
// finest shards are those, and the shards above them.
bool mayHoldSource(const PyramidLayout& layout, const Source& source, const ShardId& shard) {
    if (coversTheGlobe(source.grid)) return true;
    for (ShardId s = shard; s.level > kOffset; s = {s.level - 1, s.x / 2, s.y / 2})
        if (!reachesSource(boxOfShard(layout, s, source.faceFinestLevel), source.grid))
            return false;
    return true;
}

std::vector<ShardId> childShards(const PyramidLayout& layout, const ShardId& s) {
    std::vector<ShardId> children;
    for (std::int64_t dy = 0; dy < 2; ++dy)
        for (std::int64_t dx = 0; dx < 2; ++dx) {
            const ShardId child{s.level + 1, 2 * s.x + dx, 2 * s.y + dy};
            if (layout.contains(child)) children.push_back(child);
        }
    return children;
}

std::vector<std::vector<ShardId>> plannedShards(const PyramidLayout& layout, const Source& source) {
    if (coversTheGlobe(source.grid)) {
        std::vector<std::vector<ShardId>> all(static_cast<std::size_t>(layout.levelCount()));
        for (int level = kOffset; level <= layout.finestLevel(); ++level)
            for (std::int64_t y = 0; y < layout.shardsY(level); ++y)
                for (std::int64_t x = 0; x < layout.shardsX(level); ++x)
                    all[static_cast<std::size_t>(level)].push_back({level, x, y});
        return all;
    }
    std::vector<std::set<std::pair<std::int64_t, std::int64_t>>> byLevel(
        static_cast<std::size_t>(layout.levelCount()));
    const int finest = layout.finestLevel();
    std::vector<ShardId> stack;
    for (std::int64_t y = 0; y < layout.shardsY(kOffset); ++y)
        for (std::int64_t x = 0; x < layout.shardsX(kOffset); ++x) {
            byLevel[kOffset].insert({y, x});  // the faces' own, always
            stack.push_back({kOffset, x, y});
        }
    while (!stack.empty()) {
        const ShardId s = stack.back();
        stack.pop_back();
        if (s.level > kOffset &&
            !reachesSource(boxOfShard(layout, s, source.faceFinestLevel), source.grid))
            continue;
        if (s.level == finest) {
            for (ShardId a = s; a.level >= kOffset; a = {a.level - 1, a.x / 2, a.y / 2})
                byLevel[static_cast<std::size_t>(a.level)].insert({a.y, a.x});
            continue;
        }
        for (const ShardId& child : childShards(layout, s)) stack.push_back(child);
    }
    std::vector<std::vector<ShardId>> shards(byLevel.size());
    for (std::size_t level = 0; level < byLevel.size(); ++level)
        for (const auto& [y, x] : byLevel[level])
            shards[level].push_back({static_cast<int>(level), x, y});
    return shards;
}

// ---------------------------------------------------------------------------------------
// Building a shard.

// Bytes a globe shard task needs besides its block cache, about; a task refuses a budget below
// twice it (ShardPlan::taskBytes).
std::uint64_t globeShardBytes(const PyramidLayout& layout) {
    const auto patches =
        std::uint64_t(layout.shardPatches()) * std::uint64_t(layout.shardPatches());
    const auto tile = std::uint64_t(layout.tileSamples()) * std::uint64_t(layout.tileSamples());
    const auto drawn = std::uint64_t(layout.patchSamples()) * std::uint64_t(layout.patchSamples());
    // Per patch: its record and the places of its samples while resampling (tile · 45 bytes),
    // its surface (drawn · 24), its evens and its children's (drawn · 5 / 4 · 5).
    return patches * (tile * 45 + drawn * 24 + drawn * 7) + (std::uint64_t{1} << 19);
}

// A parent's task reads its children's carries whole: patches of `quads` quads.
Status checkPatchCarry(const fs::path& path, const detail::RegionCarry& c, int quads) {
    const std::size_t patches = c.keys.size();
    const auto half = static_cast<std::size_t>(quads / 2);
    const std::size_t samples = patches * (half + 1) * (half + 1);
    if (c.evenHeights.size() != samples ||
        (!c.parentLow.empty() && c.parentLow.size() != patches * half * half))
        return Error{path.string() + ": inconsistent globe shard carry file"};
    return {};
}

// Levels above the finest whose Err(P) is measured at the source's samples, as the whole build
// measures every level, before the nested bound takes over: each costs a pass over the source
// as the finest level's does, and they are the levels a flight draws most of its patches
// from between orbit and the ground, where the nested bound would cost triangles.
constexpr int kMeasuredLevelsAboveFinest = 2;  // PyramidBuildOptions::globeMeasuredLevels
// And any shard whose surroundings hold this many samples or fewer (a small source: every
// level).
constexpr std::int64_t kMeasuredWindowSamples = std::int64_t{1} << 24;

std::int64_t samplesIn(const SourceWindow& window) {
    std::int64_t columns = 0;
    for (const ColumnRange& c : window.columns) columns += c.end - c.first;
    return columns * (window.row1 - window.row0);
}

bool measuredAtSamples(int faceLevel, int faceFinestLevel, const SourceWindow& window,
                       const PyramidBuildOptions& options) {
    if (options.globeMeasuredLevels >= 0)
        return faceLevel >= faceFinestLevel - options.globeMeasuredLevels;
    return faceLevel >= faceFinestLevel - kMeasuredLevelsAboveFinest ||
           samplesIn(window) <= kMeasuredWindowSamples;
}

// Signed intervals per quad, rounded outwards to floats.
struct QuadIntervals {
    std::vector<float> low, high;
    void reset(std::size_t count) {
        low.assign(count, std::numeric_limits<float>::infinity());
        high.assign(count, -std::numeric_limits<float>::infinity());
    }
    void widen(std::size_t quad, double lowest, double highest) {
        low[quad] = std::min(low[quad], roundDown(lowest));
        high[quad] = std::max(high[quad], roundUpToFloat(highest));
    }
    bool holds(std::size_t quad) const { return low[quad] <= high[quad]; }
    double largest() const {
        double error = 0.0;
        for (std::size_t q = 0; q < low.size(); ++q)
            if (holds(q))
                error = std::max({error, std::abs(double(low[q])), std::abs(double(high[q]))});
        return error;
    }
    static float roundDown(double value) { return -roundUpToFloat(-value); }
};

struct Patch {
    PatchRecord record;
    std::vector<float> evens;  // unrounded even samples, (q/2 + 1)², row-major
    std::vector<std::uint8_t> evenValid;
    // Per quad (q², row-major): how far its drawn surface lies above (+) or below (−) the
    // source samples in the quad, the lowest and highest (either diagonal); low > high where
    // the quad holds no valid sample. Err(P) is the largest |·| of them, and the parent's
    // intervals are made from them (carryToParents).
    QuadIntervals quads;
    double error = 0.0;
    double childrenError = 0.0;  // the largest of its children's
    double quantized = 0.0;
    std::uint8_t presentChildren = 0;
};

class ShardBuilder {
public:
    ShardBuilder(DemReader& reader, detail::SourceVoids& voids, const Source& source,
                 const ShardPlan& plan, const ShardId& shard, const PyramidBuildOptions& options)
        : m_reader(reader),
          m_voids(voids),
          m_source(source),
          m_plan(plan),
          m_layout(plan.layout),
          m_shard(shard),
          m_level(shard.level - kOffset),
          m_options(options),
          m_quads(plan.layout.patchQuads()),
          m_tile(plan.layout.tileSamples()),
          m_threads(options.threads != 0 ? options.threads
                                         : std::max(1u, std::thread::hardware_concurrency())) {
        if (options.maxErrorM > 0.0) m_quantization = ManifestQuantization{options.maxErrorM};
        m_carry.fingerprint = plan.fingerprint;
        m_carry.shard = shard;
    }

    Status run() {
        const std::uint64_t fixed = globeShardBytes(m_layout);
        const std::uint64_t cache =
            m_options.memoryBudgetBytes > fixed ? m_options.memoryBudgetBytes - fixed : 0;
        // A shard measured at the source's samples reads its whole neighbourhood, in blocks of
        // up to half of it (so that the blocks straddling its edges read little beyond it); a
        // nested one only its patches' edges, in small blocks.
        const bool finest = m_level == m_plan.faceFinestLevel;
        std::int64_t blockRows = 32, blockColumns = 128;
        const SourceWindow window =
            windowOf(boxOfShard(m_layout, m_shard, m_plan.faceFinestLevel), m_source.grid);
        const bool measured = measuredAtSamples(m_level, m_plan.faceFinestLevel, window, m_options);
        if (measured) {
            std::int64_t widest = 0;
            for (const ColumnRange& c : window.columns) widest = std::max(widest, c.end - c.first);
            const auto halfOf = [](std::int64_t span, std::int64_t low, std::int64_t high) {
                std::int64_t size = low;
                while (size * 4 <= span && size < high) size *= 2;
                return size;
            };
            blockRows = halfOf(window.row1 - window.row0, 16, 128);
            blockColumns = halfOf(widest, 64, 512);
        }
        m_blocks = std::make_unique<detail::GeographicBlocks>(m_reader, m_voids, m_source.grid,
                                                              cache, blockRows, blockColumns);
        auto start = BuildClock::now();
        if (Status built = finest ? buildFinest(window) : buildCoarse(); !built) return built;
        if (measured)
            if (Status made = measureAtSamples(window); !made) return made;
        if (Status made = measureTaper(); !made) return made;
        m_carry.phases.readSeconds += secondsSince(start);
        start = BuildClock::now();
        // Each patch's bounds on every thread (λ(d) is most of their time), then gathered.
        std::vector<Patch*> finishing;
        finishing.reserve(m_patches.size());
        for (auto& [key, patch] : m_patches) finishing.push_back(&patch);
        parallelFor(std::ssize(finishing), m_threads, [&](std::int64_t i) {
            Patch& patch = *finishing[static_cast<std::size_t>(i)];
            detail::finishGlobePatch(m_layout, m_level, patch.error, patch.presentChildren,
                                     m_quantization, patch.quantized, patch.record);
        });
        std::vector<const PatchRecord*> records;
        for (auto& [key, patch] : m_patches) {
            m_carry.levelMaxError = std::max(m_carry.levelMaxError, patch.record.info.error);
            if (m_quantization && finest)
                m_carry.finestLargestQuantErrorM =
                    std::max(m_carry.finestLargestQuantErrorM, patch.quantized);
            records.push_back(&patch.record);
        }
        if (m_level > 0) {
            // A parent measured at the samples needs no intervals from its children.
            const ShardId parent{m_shard.level - 1, m_shard.x / 2, m_shard.y / 2};
            const bool parentNested = !measuredAtSamples(
                m_level - 1, m_plan.faceFinestLevel,
                windowOf(boxOfShard(m_layout, parent, m_plan.faceFinestLevel), m_source.grid),
                m_options);
            carryToParents(parentNested);
        }
        m_carry.phases.boundsSeconds += secondsSince(start);
        start = BuildClock::now();
        m_carry.patches = std::ssize(records);
        if (!records.empty()) {
            ShardWriterOptions writerOptions;
            writerOptions.compressionLevel = m_options.compressionLevel;
            if (Status written = detail::writeGlobeShard(m_plan.staging, m_layout, m_shard, records,
                                                         writerOptions, m_quantization, m_threads);
                !written)
                return written;
        }
        m_carry.phases.writeSeconds += secondsSince(start);
        return {};
    }

    detail::RegionCarry& carry() { return m_carry; }

private:
    bool inShard(PatchKey key) const {
        const GlobePatchId id = idOf(key, m_level);
        return m_layout.shardOf(layoutPatchOf(id)) == m_shard;
    }

    bool cancelled() const { return m_options.cancel != nullptr && m_options.cancel->load(); }

    // One row of a piece of the window around the shard: its samples and their patches.
    struct SampleRow {
        std::int64_t row = 0, column0 = 0, count = 0;
        const float* heights = nullptr;
        const std::uint8_t* valid = nullptr;
        const PatchKey* keys = nullptr;            // of each sample's patch at this level
        const globe::FacePoint* points = nullptr;  // each sample's place on its face
        const glm::dvec3* normals = nullptr;       // and its normal (Wgs84::normalAt)
        globe::Wgs84::RadiiAlongNormal radii{};    // the ellipsoid's at the row's latitude
    };

    // Every source sample of the window, piece by piece, rows in parallel.
    template <typename VisitRow>
    Status forEachRow(const SourceWindow& window, VisitRow&& visitRow) {
        const GeographicGrid& g = m_source.grid;
        const std::int64_t n = globe::patchesPerFaceSide(m_level);
        for (const ColumnRange& columns : window.columns) {
            Status status = m_blocks->forEachPiece(
                window.row0, window.row1, columns.first, columns.end,
                [&](const detail::GeographicBlocks::Piece& piece) {
                    // Wgs84::normalAt's terms, each column's computed once for all rows.
                    std::vector<double> cosLon(static_cast<std::size_t>(piece.columns));
                    std::vector<double> sinLon(cosLon.size());
                    for (std::size_t c = 0; c < cosLon.size(); ++c) {
                        const double lon = g.longitudeOf(piece.column0 + std::int64_t(c)) * kDegree;
                        cosLon[c] = std::cos(lon);
                        sinLon[c] = std::sin(lon);
                    }
                    parallelFor(piece.rows, m_threads, [&](std::int64_t r) {
                        const std::int64_t row = piece.row0 + r;
                        const double lat = g.latitudeOf(row) * kDegree;
                        const double cosLat = std::cos(lat), sinLat = std::sin(lat);
                        std::vector<PatchKey> keys(static_cast<std::size_t>(piece.columns));
                        std::vector<globe::FacePoint> points(keys.size());
                        std::vector<glm::dvec3> normals(keys.size());
                        for (std::size_t k = 0; k < keys.size(); ++k) {
                            normals[k] = {cosLat * cosLon[k], cosLat * sinLon[k], sinLat};
                            points[k] = globe::facePointOf(normals[k]);
                            keys[k] = keyOf(points[k].face, patchIndex(points[k].s, n),
                                            patchIndex(points[k].t, n));
                        }
                        const auto at = static_cast<std::size_t>(r * piece.stride);
                        visitRow(SampleRow{row, piece.column0, piece.columns, piece.heights + at,
                                           piece.valid + at, keys.data(), points.data(),
                                           normals.data(),
                                           globe::Wgs84::radiiAlongNormal(sinLat, 0.0)});
                    });
                });
            if (!status) return status;
            if (cancelled()) return Error{"the build was cancelled"};
        }
        return {};
    }

    // The tile samples' heights of `keys`' patches where `fromSource` says so, resampled from
    // the source as the whole build does (GeographicGrid::at); true per patch when a drawn
    // sample lies inside the source's extent.
    Result<std::vector<std::uint8_t>> resample(
        const std::vector<PatchKey>& keys,
        const std::function<bool(std::size_t patch, int i, int j)>& fromSource) {
        const auto perPatch = static_cast<std::size_t>(m_tile * m_tile);
        std::vector<globe::Geodetic> places(keys.size() * perPatch);
        std::vector<std::uint8_t> wanted(places.size(), 0);
        parallelFor(std::ssize(keys), m_threads, [&](std::int64_t k) {
            const GlobePatchId id = idOf(keys[static_cast<std::size_t>(k)], m_level);
            const globe::PatchSampleDirections directions(id, m_quads, -1, m_quads + 1);
            for (int j = -1; j <= m_quads + 1; ++j)
                for (int i = -1; i <= m_quads + 1; ++i) {
                    const std::size_t at = static_cast<std::size_t>(k) * perPatch +
                                           static_cast<std::size_t>((j + 1) * m_tile + i + 1);
                    if (!fromSource(static_cast<std::size_t>(k), i, j)) continue;
                    wanted[at] = 1;
                    places[at] = globe::Wgs84::geodeticOfNormal(directions(i, j));
                }
        });
        std::vector<std::uint8_t> insideAny(keys.size(), 0);
        for (std::size_t k = 0; k < keys.size(); ++k) {
            PatchRecord& record = m_patches.at(keys[k]).record;
            for (int j = -1; j <= m_quads + 1; ++j)
                for (int i = -1; i <= m_quads + 1; ++i) {
                    const auto local = static_cast<std::size_t>((j + 1) * m_tile + i + 1);
                    const std::size_t at = k * perPatch + local;
                    if (!wanted[at]) continue;
                    Result<GeographicGrid::Resampled> value =
                        m_blocks->at(places[at].latitudeDeg, places[at].longitudeDeg);
                    if (!value) return value.error();
                    record.heights[local] = value.value().height;
                    record.valid[local] = value.value().valid ? 1 : 0;
                    const bool drawn = i >= 0 && j >= 0 && i <= m_quads && j <= m_quads;
                    if (drawn && value.value().inside) insideAny[k] = 1;
                }
            if (cancelled()) return Error{"the build was cancelled"};
        }
        return insideAny;
    }

    Patch& addPatch(PatchKey key) {
        Patch& patch = m_patches[key];
        patch.record.id = layoutPatchOf(idOf(key, m_level));
        patch.record.heights.assign(static_cast<std::size_t>(m_tile * m_tile), 0.0f);
        patch.record.valid.assign(patch.record.heights.size(), 0);
        return patch;
    }

    // Keeps the unrounded even samples for the parent, then rounds a lossy build's heights
    // (Yusov §4) before Err(P) is made on them.
    void keepEvensAndRound(Patch& patch) {
        const int half = m_quads / 2;
        patch.evens.clear();
        patch.evenValid.clear();
        for (int b = 0; b <= half; ++b)
            for (int a = 0; a <= half; ++a) {
                const auto at = static_cast<std::size_t>((2 * b + 1) * m_tile + 2 * a + 1);
                patch.evens.push_back(patch.record.heights[at]);
                patch.evenValid.push_back(patch.record.valid[at]);
            }
        if (m_quantization)
            patch.quantized = quantizeHeights(
                patch.record.heights, detail::globeHalfStep(*m_quantization, m_layout, m_level));
    }

    // The finest level: as GlobePyramidBuilder builds it, within the samples around the shard.
    Status buildFinest(const SourceWindow& window) {
        // The patches holding source samples (around the shard too), and the statistics of
        // the shard's own samples.
        std::unordered_set<PatchKey> holding;
        std::mutex merge;
        Status read = forEachRow(window, [&](const SampleRow& r) {
            std::vector<PatchKey> seen;
            detail::DemStatistics counts;  // this row's
            bool inThisShard = false;
            for (std::int64_t c = 0; c < r.count; ++c) {
                if (seen.empty() || r.keys[c] != seen.back()) {
                    seen.push_back(r.keys[c]);
                    inThisShard = inShard(r.keys[c]);
                }
                if (!inThisShard) continue;
                if (!r.valid[c]) {
                    ++counts.noDataSamples;
                    continue;
                }
                ++counts.validSamples;
                counts.minHeight = std::min(counts.minHeight, double(r.heights[c]));
                counts.maxHeight = std::max(counts.maxHeight, double(r.heights[c]));
            }
            const std::scoped_lock lock(merge);
            holding.insert(seen.begin(), seen.end());
            m_carry.statistics.add(counts);
        });
        if (!read) return read;
        // The shard's patches the whole build considers (GlobePyramidBuilder: holding ones and
        // their neighbours two away; at face level 0, the faces).
        std::set<PatchKey> candidates;
        std::unordered_set<PatchKey> around;
        for (const PatchKey key : holding) {
            around.clear();
            around.insert(key);
            detail::addPatchesAround(key, m_level, around);
            for (const PatchKey k : around)
                if (inShard(k)) candidates.insert(k);
        }
        if (m_level == 0)
            for (const FaceRect& r : faceRectsOf(m_layout, m_shard))
                candidates.insert(keyOf(r.face, 0, 0));
        std::vector<PatchKey> keys(candidates.begin(), candidates.end());
        for (const PatchKey key : keys) addPatch(key);
        Result<std::vector<std::uint8_t>> inside =
            resample(keys, [](std::size_t, int, int) { return true; });
        if (!inside) return inside.error();
        for (std::size_t k = 0; k < keys.size(); ++k)
            if (!(holding.contains(keys[k]) || inside.value()[k] || m_level == 0))
                m_patches.erase(keys[k]);
        if (Status siblings = addSiblings(); !siblings) return siblings;
        for (auto& [key, patch] : m_patches) keepEvensAndRound(patch);
        return {};
    }

    // The present patches' siblings, from the source, as the whole build adds them
    // (detail::forEachSibling). A shard holds whole sibling sets: it is aligned to an even
    // number of patches.
    Status addSiblings() {
        std::set<PatchKey> siblings;
        for (const auto& [key, patch] : m_patches)
            detail::forEachSibling(key, m_level, [&](PatchKey sibling) {
                if (!m_patches.contains(sibling)) siblings.insert(sibling);
            });
        const std::vector<PatchKey> keys(siblings.begin(), siblings.end());
        for (const PatchKey key : keys) addPatch(key);
        Result<std::vector<std::uint8_t>> resampled =
            resample(keys, [](std::size_t, int, int) { return true; });
        if (!resampled) return resampled.error();
        return {};
    }

    // Err(P) at every valid source sample in a patch of the shard (a single source shows all
    // of its valid samples: GlobeSources::measuredSample).
    Status measureAtSamples(const SourceWindow& window) {
        std::unordered_map<PatchKey, std::unique_ptr<GlobePatchSurface>> surfaces;
        for (auto& [key, patch] : m_patches) surfaces[key] = nullptr;
        std::vector<PatchKey> keys;
        for (const auto& [key, patch] : m_patches) keys.push_back(key);
        parallelFor(std::ssize(keys), m_threads, [&](std::int64_t k) {
            const PatchKey key = keys[static_cast<std::size_t>(k)];
            // Each task writes its own entry, made above: no rehash, no race.
            surfaces.find(key)->second = std::make_unique<GlobePatchSurface>(
                idOf(key, m_level), m_quads, m_patches.at(key).record.heights);
        });
        for (auto& [key, patch] : m_patches)
            patch.quads.reset(static_cast<std::size_t>(m_quads * m_quads));
        std::mutex merge;
        Status measured = forEachRow(window, [&](const SampleRow& r) {
            // This row's lowest and highest surface − sample, a run of samples in one quad at
            // a time (a row's samples stay in a patch, and in a quad, for stretches): each
            // run's extremes are widened into the quad once, under the lock, at the row's end.
            // min and max in any order give the same intervals.
            struct Run {
                Patch* patch = nullptr;
                int quad = -1;
                double lowest = 0.0, highest = 0.0;
            };
            std::vector<Run> runs;
            PatchKey lastKey = 0;
            const GlobePatchSurface* surface = nullptr;
            Patch* patch = nullptr;
            bool looked = false;
            for (std::int64_t c = 0; c < r.count; ++c) {
                if (!r.valid[c]) continue;
                if (!looked || r.keys[c] != lastKey) {
                    lastKey = r.keys[c];
                    looked = true;
                    const auto found = surfaces.find(lastKey);
                    surface = found == surfaces.end() ? nullptr : found->second.get();
                    patch = surface == nullptr ? nullptr : &m_patches.at(lastKey);
                }
                if (surface == nullptr) continue;
                const int quad = quadOf(lastKey, r.points[c].s, r.points[c].t);
                const auto [alongAD, alongBC] =
                    surface->drawnHeights(r.normals[c], r.points[c],
                                          globe::Wgs84::pointAlongNormal(r.normals[c], r.radii));
                const double height = double(r.heights[c]);
                const double lowest = std::min(alongAD, alongBC) - height;
                const double highest = std::max(alongAD, alongBC) - height;
                if (!runs.empty() && runs.back().patch == patch && runs.back().quad == quad) {
                    runs.back().lowest = std::min(runs.back().lowest, lowest);
                    runs.back().highest = std::max(runs.back().highest, highest);
                } else {
                    runs.push_back({patch, quad, lowest, highest});
                }
            }
            const std::scoped_lock lock(merge);
            for (const Run& run : runs)
                run.patch->quads.widen(static_cast<std::size_t>(run.quad), run.lowest, run.highest);
        });
        if (!measured) return measured;
        // Err(P) at every valid sample, both diagonals, never below a child's: as the whole
        // build makes it.
        for (auto& [key, patch] : m_patches)
            patch.error = std::max(patch.childrenError, patch.quads.largest());
        return {};
    }

    // The quad of patch `key` (this level) that GlobePatchSurface::drawnHeights draws the
    // point at face coordinates (s, t) on, the point clamped into the patch.
    int quadOf(PatchKey key, double s, double t) const {
        const double n = double(globe::patchesPerFaceSide(m_level));
        const GlobePatchId id = idOf(key, m_level);
        const auto along = [&](double coordinate, std::int64_t first) {
            const double at =
                std::clamp((coordinate * n - double(first)) * m_quads, 0.0, double(m_quads));
            return std::min(static_cast<int>(at), m_quads - 1);
        };
        return along(t, id.y) * m_quads + along(s, id.x);
    }

    // Where the source's edge tapers to the bare ellipsoid (GeographicGrid::taperPlaces), on
    // every level, as the whole build measures there (one source: nothing lies beneath it). A
    // nested level needs it too: a patch's quarter without a child has no intervals from it.
    Status measureTaper() {
        const std::int64_t perSide = globe::patchesPerFaceSide(m_level);
        std::unordered_map<PatchKey, std::unique_ptr<GlobePatchSurface>> surfaces;
        for (const auto& [latitude, longitude] : m_source.grid.taperPlaces()) {
            const glm::dvec3 normal = globe::Wgs84::normalAt(latitude, longitude);
            const globe::FacePoint p = globe::facePointOf(normal);
            const PatchKey key = keyOf(p.face, patchIndex(p.s, perSide), patchIndex(p.t, perSide));
            const auto patch = m_patches.find(key);
            if (patch == m_patches.end()) continue;
            std::unique_ptr<GlobePatchSurface>& surface = surfaces[key];
            if (!surface)
                surface = std::make_unique<GlobePatchSurface>(idOf(key, m_level), m_quads,
                                                              patch->second.record.heights);
            Result<GeographicGrid::Resampled> value = m_blocks->at(latitude, longitude);
            if (!value) return value.error();
            const int quad = quadOf(key, p.s, p.t);
            const auto [alongAD, alongBC] = surface->drawnHeights(normal, p);
            const double height = double(value.value().height);
            patch->second.quads.widen(static_cast<std::size_t>(quad),
                                      std::min(alongAD, alongBC) - height,
                                      std::max(alongAD, alongBC) - height);
        }
        for (auto& [key, patch] : m_patches)
            patch.error = std::max(patch.error, patch.quads.largest());
        return {};
    }

    // A coarser level: from the carries of the shards beneath.
    Status buildCoarse() {
        struct Child {
            float error = 0.0f;  // its Err(P)
            const float* evens = nullptr;
            const std::uint8_t* valid = nullptr;
            const float* low = nullptr;  // this level's quads over it: intervals
            const float* high = nullptr;
        };
        const int half = m_quads / 2;
        const auto evenCount = static_cast<std::size_t>((half + 1) * (half + 1));
        const auto quadCount = static_cast<std::size_t>(half * half);
        std::vector<detail::RegionCarry> carries;
        std::unordered_map<PatchKey, Child> children;
        for (const ShardId& child : childShards(m_layout, m_shard)) {
            const fs::path path = detail::carryPath(m_plan.staging, child);
            std::error_code ec;
            if (!fs::exists(path, ec)) continue;  // not planned, or not built: the merge tells
            auto read = detail::readShardCarry(m_plan.staging, child, m_plan.fingerprint, true);
            if (!read) return read.error();
            if (Status fits = checkPatchCarry(path, read.value(), m_quads); !fits) return fits;
            m_carry.builtFrom.push_back(child);
            carries.push_back(std::move(read).value());
        }
        for (const detail::RegionCarry& c : carries)
            for (std::size_t k = 0; k < c.keys.size(); ++k)
                children[c.keys[k]] = {
                    c.errors[k], c.evenHeights.data() + k * evenCount,
                    c.evenValid.data() + k * evenCount,
                    c.parentLow.empty() ? nullptr : c.parentLow.data() + k * quadCount,
                    c.parentHigh.empty() ? nullptr : c.parentHigh.data() + k * quadCount};
        for (const auto& [childKey, child] : children) {
            const GlobePatchId id = idOf(childKey, m_level + 1);
            const PatchKey parent = keyOf(id.face, id.x / 2, id.y / 2);
            addPatch(parent);
            detail::forEachSibling(parent, m_level, [&](PatchKey sibling) { addPatch(sibling); });
        }
        if (m_level == 0)
            for (const FaceRect& r : faceRectsOf(m_layout, m_shard)) addPatch(keyOf(r.face, 0, 0));

        // Each patch's samples from its children's even samples where a child is present.
        std::vector<PatchKey> keys;
        for (const auto& [key, patch] : m_patches) keys.push_back(key);
        std::vector<std::array<const Child*, 4>> present(keys.size());
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const GlobePatchId id = idOf(keys[k], m_level);
            Patch& patch = m_patches.at(keys[k]);
            patch.quads.reset(static_cast<std::size_t>(m_quads * m_quads));
            for (int c = 0; c < 4; ++c) {
                const auto found =
                    children.find(keyOf(id.face, 2 * id.x + (c & 1), 2 * id.y + (c >> 1)));
                present[k][static_cast<std::size_t>(c)] =
                    found == children.end() ? nullptr : &found->second;
                if (found == children.end()) continue;
                patch.presentChildren =
                    static_cast<std::uint8_t>(patch.presentChildren | (1u << c));
                // Never below a child's: Err(P) does not grow with depth.
                patch.childrenError = std::max(patch.childrenError, double(found->second.error));
                if (found->second.low == nullptr) continue;  // this shard is measured
                for (int b = 0; b < half; ++b)
                    for (int a = 0; a < half; ++a) {
                        const auto from = static_cast<std::size_t>(b * half + a);
                        const auto to = static_cast<std::size_t>(((c >> 1) * half + b) * m_quads +
                                                                 (c & 1) * half + a);
                        patch.quads.low[to] = found->second.low[from];
                        patch.quads.high[to] = found->second.high[from];
                    }
            }
            patch.error = std::max(patch.childrenError, patch.quads.largest());
        }
        // The child holding sample (i, j) of the patch, and the sample's index among its evens.
        const auto childSample = [&](std::size_t k, int i, int j) -> std::pair<const Child*, int> {
            if (i < 0 || j < 0 || i > m_quads || j > m_quads) return {nullptr, 0};
            for (int cy = (j < half ? 0 : j > half ? 1 : 0); cy <= (j < half ? 0 : 1); ++cy)
                for (int cx = (i < half ? 0 : i > half ? 1 : 0); cx <= (i < half ? 0 : 1); ++cx) {
                    const Child* c = present[k][static_cast<std::size_t>(cy * 2 + cx)];
                    if (c != nullptr) return {c, (j - cy * half) * (half + 1) + (i - cx * half)};
                }
            return {nullptr, 0};
        };
        for (std::size_t k = 0; k < keys.size(); ++k) {
            PatchRecord& record = m_patches.at(keys[k]).record;
            for (int j = 0; j <= m_quads; ++j)
                for (int i = 0; i <= m_quads; ++i) {
                    const auto [child, at] = childSample(k, i, j);
                    if (child == nullptr) continue;
                    const auto local = static_cast<std::size_t>((j + 1) * m_tile + i + 1);
                    record.heights[local] = child->evens[at];
                    record.valid[local] = child->valid[at];
                }
        }
        // The apron, and what no child covers, from the source.
        Result<std::vector<std::uint8_t>> resampled = resample(
            keys,
            [&](std::size_t k, int i, int j) { return childSample(k, i, j).first == nullptr; });
        if (!resampled) return resampled.error();
        for (auto& [key, patch] : m_patches) keepEvensAndRound(patch);
        return {};
    }

    // What this patch tells its parent about the source samples under it (Yusov & Shevtsov
    // 2011, §4, nested, here signed and per quad): for a sample s in one of this patch's quads,
    // parent(s) − s = (parent − this)(s) + (this − s). The second term lies in the quad's
    // interval; the first, on one quad, is linear on the triangles of the diagonals either
    // surface is drawn with, so it lies between its values at the quad's corners and, where
    // the diagonals cross, its centre, every diagonal of both taken. The parent's surface here
    // is made of this patch's even samples, rounded as the parent rounds them. Each parent
    // quad (2 × 2 of this patch's) gets the union of its quads' sums: where the two terms
    // differ in sign they cancel, as they do in the samples, and the bound does not add the
    // levels' largest differences wherever they lie. Only for a nested parent: one measured at
    // the samples needs the evens alone.
    void carryToParents(bool parentNested) {
        const int half = m_quads / 2;
        const std::int64_t n = globe::patchesPerFaceSide(m_level);
        std::vector<PatchKey> keys;
        for (const auto& [key, patch] : m_patches) keys.push_back(key);
        const auto perPatch = static_cast<std::size_t>(half * half);
        std::vector<float> parentLow(parentNested ? keys.size() * perPatch : 0);
        std::vector<float> parentHigh(parentLow.size());
        parallelFor(parentNested ? std::ssize(keys) : 0, m_threads, [&](std::int64_t k) {
            const PatchKey key = keys[static_cast<std::size_t>(k)];
            const Patch& patch = m_patches.at(key);
            const GlobePatchId id = idOf(key, m_level);
            const GlobePatchId parent{id.face, m_level - 1, id.x / 2, id.y / 2};
            const int offsetX = int(id.x & 1) * half, offsetY = int(id.y & 1) * half;
            // The parent's tile: this patch's evens in its quarter, the nearest of them
            // elsewhere (never drawn here: only this quarter is measured).
            std::vector<float> parentTile(static_cast<std::size_t>(m_tile * m_tile));
            for (int j = -1; j <= m_quads + 1; ++j)
                for (int i = -1; i <= m_quads + 1; ++i) {
                    const int a = std::clamp(i - offsetX, 0, half);
                    const int b = std::clamp(j - offsetY, 0, half);
                    parentTile[static_cast<std::size_t>((j + 1) * m_tile + i + 1)] =
                        patch.evens[static_cast<std::size_t>(b * (half + 1) + a)];
                }
            if (m_quantization)
                quantizeHeights(parentTile,
                                detail::globeHalfStep(*m_quantization, m_layout, m_level - 1));
            const GlobePatchSurface parentSurface(parent, m_quads, parentTile);
            const GlobePatchSurface surface(id, m_quads, patch.record.heights);
            const double denominator = double(n) * m_quads;
            // parent − this at a point, its lowest and highest over the diagonals.
            const auto difference = [&](double i, double j) {
                const glm::dvec3 normal =
                    globe::directionOf(id.face, (double(id.x) * m_quads + i) / denominator,
                                       (double(id.y) * m_quads + j) / denominator);
                const auto [parentAD, parentBC] = parentSurface.drawnHeights(normal);
                const auto [childAD, childBC] = surface.drawnHeights(normal);
                return std::pair(std::min(parentAD, parentBC) - std::max(childAD, childBC),
                                 std::max(parentAD, parentBC) - std::min(childAD, childBC));
            };
            // At the vertices of quads holding samples only: elsewhere no sample is drawn by
            // either (beyond the source's edge the two may differ by its cliff).
            const auto vertexIndex = [&](int i, int j) {
                return static_cast<std::size_t>(j * (m_quads + 1) + i);
            };
            std::vector<std::pair<double, double>> atVertex(
                static_cast<std::size_t>((m_quads + 1) * (m_quads + 1)));
            std::vector<std::uint8_t> needed(atVertex.size(), 0);
            for (int j = 0; j < m_quads; ++j)
                for (int i = 0; i < m_quads; ++i)
                    if (patch.quads.holds(static_cast<std::size_t>(j * m_quads + i)))
                        for (int corner = 0; corner < 4; ++corner)
                            needed[vertexIndex(i + (corner & 1), j + (corner >> 1))] = 1;
            for (int j = 0; j <= m_quads; ++j)
                for (int i = 0; i <= m_quads; ++i)
                    if (needed[vertexIndex(i, j)]) atVertex[vertexIndex(i, j)] = difference(i, j);
            const std::size_t first = static_cast<std::size_t>(k) * perPatch;
            std::fill_n(parentLow.begin() + std::ptrdiff_t(first), perPatch,
                        std::numeric_limits<float>::infinity());
            std::fill_n(parentHigh.begin() + std::ptrdiff_t(first), perPatch,
                        -std::numeric_limits<float>::infinity());
            for (int j = 0; j < m_quads; ++j)
                for (int i = 0; i < m_quads; ++i) {
                    const auto quad = static_cast<std::size_t>(j * m_quads + i);
                    if (!patch.quads.holds(quad)) continue;
                    auto [low, high] = difference(i + 0.5, j + 0.5);
                    for (int corner = 0; corner < 4; ++corner) {
                        const auto& v = atVertex[vertexIndex(i + (corner & 1), j + (corner >> 1))];
                        low = std::min(low, v.first);
                        high = std::max(high, v.second);
                    }
                    const std::size_t to = first + static_cast<std::size_t>((j / 2) * half + i / 2);
                    parentLow[to] = std::min(parentLow[to],
                                             QuadIntervals::roundDown(low + patch.quads.low[quad]));
                    parentHigh[to] =
                        std::max(parentHigh[to], roundUpToFloat(high + patch.quads.high[quad]));
                }
        });
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const Patch& patch = m_patches.at(keys[k]);
            m_carry.keys.push_back(keys[k]);
            m_carry.errors.push_back(roundUpToFloat(patch.error));
            m_carry.evenHeights.insert(m_carry.evenHeights.end(), patch.evens.begin(),
                                       patch.evens.end());
            m_carry.evenValid.insert(m_carry.evenValid.end(), patch.evenValid.begin(),
                                     patch.evenValid.end());
        }
        m_carry.parentLow = std::move(parentLow);
        m_carry.parentHigh = std::move(parentHigh);
    }

    DemReader& m_reader;
    detail::SourceVoids& m_voids;
    const Source& m_source;
    const ShardPlan& m_plan;
    const PyramidLayout& m_layout;
    ShardId m_shard;
    int m_level;  // the face level
    const PyramidBuildOptions& m_options;
    int m_quads, m_tile;
    unsigned m_threads;
    std::optional<ManifestQuantization> m_quantization;
    std::unique_ptr<detail::GeographicBlocks> m_blocks;
    std::map<PatchKey, Patch> m_patches;  // ordered: the shard's bytes do not depend on hashing
    detail::RegionCarry m_carry;
};

class GlobeShardTiling final : public detail::ShardTiling {
public:
    GlobeShardTiling(DemReader& reader, Source source, const PyramidBuildOptions& options)
        : m_reader(reader), m_voids(reader), m_source(std::move(source)), m_options(options) {}

    static Result<std::unique_ptr<detail::ShardTiling>> open(DemReader& reader,
                                                             const fs::path& output,
                                                             const PyramidBuildOptions& options,
                                                             bool listShards) {
        const DemInfo& dem = reader.info();
        Result<Source> described =
            describeSource(reader, options.patchSamples - 1, options.globeOversampleLevels);
        if (!described) return described.error();
        auto tiling =
            std::make_unique<GlobeShardTiling>(reader, std::move(described).value(), options);
        const int faceFinestLevel = tiling->m_source.faceFinestLevel;
        auto layout = globeLayout(faceFinestLevel, options.patchSamples, options.blockQuads,
                                  options.shardPatches);
        if (!layout) return Error{dem.path + ": " + layout.error().message};
        ShardPlan& plan = tiling->m_plan;
        plan.surface = PyramidSurface::Globe;
        plan.layout = layout.value();
        plan.faceFinestLevel = faceFinestLevel;
        plan.staging = shardStagingFolder(output);
        plan.fingerprint = globeFingerprint(dem, plan.layout, options);
        // Its patches, and as much again for its cache of source blocks.
        plan.taskBytes = 2 * globeShardBytes(plan.layout);
        if (listShards) plan.shards = plannedShards(plan.layout, tiling->m_source);
        return std::unique_ptr<detail::ShardTiling>(std::move(tiling));
    }

    std::string taskName() const override {
        return fmt::format("a globe shard of {} × {} patches", m_plan.layout.shardPatches(),
                           m_plan.layout.shardPatches());
    }

    Status checkShard(const ShardId& shard, const fs::path& output) const override {
        const PyramidLayout& layout = m_plan.layout;
        if (shard.level < kOffset || shard.level > layout.finestLevel() ||
            !layout.contains(shard) || !mayHoldSource(layout, m_source, shard))
            return Error{fmt::format(
                "{}: shard {}/{}/{} is not one of this globe pyramid's (levels {} to {}; "
                "terrain-build --plan --json lists them)",
                output.string(), shard.level, shard.x, shard.y, kOffset, layout.finestLevel())};
        return {};
    }

    Result<detail::RegionCarry> buildShard(const ShardId& shard) override {
        if (!m_polesRead) {  // read once, by the first shard built
            if (Status read = detail::readPoles(m_reader, m_voids, m_source.grid); !read)
                return Error{m_reader.info().path + ": " + read.error().message};
            m_polesRead = true;
        }
        ShardBuilder builder(m_reader, m_voids, m_source, m_plan, shard, m_options);
        if (Status built = builder.run(); !built)
            return Error{m_reader.info().path + ": " + built.error().message};
        return std::move(builder.carry());
    }

    Status buildBeside(const fs::path& folder) override {
        if (!m_options.globeNativeLeaves) return {};
        auto built =
            detail::buildNativeGridByShards(m_reader, m_voids, m_source.grid, folder, m_options);
        if (!built) return built.error();
        m_nativeFolder = built.value();
        return {};
    }

    Result<PyramidManifest> manifest(const detail::RegionTotals& totals,
                                     std::vector<std::string>& warnings) override {
        const DemInfo& dem = m_reader.info();
        const detail::DemStatistics& statistics = totals.statistics;
        if (Status covered =
                detail::checkCoverage(dem.path, statistics.validSamples + statistics.noDataSamples,
                                      statistics.validSamples, warnings);
            !covered)
            return covered.error();
        DemReader* const readers[] = {&m_reader};
        ManifestGlobeSource extent = detail::globeSourceOf(m_source.grid, dem.path);
        extent.native = m_nativeFolder;
        PyramidManifest m = detail::globeManifest(m_plan.layout, m_plan.faceFinestLevel,
                                                  {std::move(extent)}, readers);
        for (ManifestLevel& level : m.levels) {  // what the shards hold
            const auto i = static_cast<std::size_t>(level.level);
            level.presentPatches = totals.presentPatches[i];
            level.presentShards = totals.presentShards[i];
            level.maxError = totals.levelMaxError[i];
        }
        m.statistics.rootError = totals.levelMaxError[static_cast<std::size_t>(kOffset)];
        m.statistics.validSamples = statistics.validSamples;
        m.statistics.minHeight = statistics.minHeight;
        m.statistics.maxHeight = statistics.maxHeight;
        m.noData.samples = statistics.noDataSamples;
        if (statistics.noDataSamples > 0) {  // one source: nothing beneath it
            m.noData.fill = ManifestNoData::kMembraneFill;
            m.noData.sources.push_back(
                {dem.path, dem.noDataValue, true, statistics.noDataSamples, 0});
        }
        m.quantization = totals.quantization;
        return m;
    }

private:
    DemReader& m_reader;
    detail::SourceVoids m_voids;  // found once for every shard this process builds
    Source m_source;
    bool m_polesRead = false;
    std::string m_nativeFolder;  // built by the merge with --native-leaves
    const PyramidBuildOptions& m_options;
};

}  // namespace

Result<std::unique_ptr<detail::ShardTiling>> detail::globeShardTiling(
    DemReader& reader, const fs::path& output, const PyramidBuildOptions& options,
    bool listShards) {
    return GlobeShardTiling::open(reader, output, options, listShards);
}

}  // namespace terrain::io
