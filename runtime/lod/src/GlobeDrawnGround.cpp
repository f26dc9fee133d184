#include "terrain/runtime/GlobeDrawnGround.h"

#include "terrain/pyramid/NativeTiles.h"
#include "terrain/runtime/NativeOwnership.h"

#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace terrain::runtime {
namespace {

// The highest of the four tile samples around patch coordinates `uv` ([0, 1]²) of a data
// patch whose tile is `tile`; nothing when the tile is malformed or one is not finite.
std::optional<double> highestSampleAround(const glm::dvec2& uv, const io::PatchRecord& tile,
                                          const io::PyramidLayout& layout) {
    const int side = layout.tileSamples();
    if (tile.heights.size() != static_cast<std::size_t>(side) * static_cast<std::size_t>(side))
        return std::nullopt;
    // Patch sample s is tile sample s + 1 (the apron), as in shaders/globe.tese.
    const double quads = layout.patchQuads();
    const int last = side - 2;
    const int x0 = std::clamp(static_cast<int>(std::floor(uv.x * quads)) + 1, 1, last);
    const int y0 = std::clamp(static_cast<int>(std::floor(uv.y * quads)) + 1, 1, last);
    double highest = -std::numeric_limits<double>::infinity();
    for (const int row : {y0, std::min(y0 + 1, last)}) {
        for (const int column : {x0, std::min(x0 + 1, last)}) {
            const float h = tile.heights[static_cast<std::size_t>(row) * std::size_t(side) +
                                         static_cast<std::size_t>(column)];
            if (!std::isfinite(h)) return std::nullopt;
            highest = std::max(highest, double(h));
        }
    }
    return highest;
}

}  // namespace

double drawnGroundCeiling(std::span<const PatchDraw> draws, const glm::dvec3& ecef) {
    const globe::FacePoint nadir = globe::facePointOf(globe::Wgs84::upAt(ecef));
    double ceiling = 0.0;
    for (const PatchDraw& draw : draws) {
        // A native tile lies over face patches the list no longer holds: its heights count
        // where the camera is over the ground it owns (NativeOwnership.h), every tile over
        // the face patch there (conservative: a ceiling); anywhere for one that owns all it
        // covers.
        if (io::isNativeTile(draw.id)) {
            const globe::GlobePatchId patch = io::globePatchOf(draw.imageryPatch);
            const double n = static_cast<double>(globe::patchesPerFaceSide(patch.level));
            if (draw.nativeCells == 0 ||
                (patch.face == nadir.face && nativeTileOwns(draw, nadir.s * n - double(patch.x),
                                                            nadir.t * n - double(patch.y))))
                ceiling = std::max(ceiling, double(draw.maxHeight));
            continue;
        }
        const globe::GlobePatchId id = io::globePatchOf(draw.id);
        if (id.face != nadir.face) continue;
        const double n = static_cast<double>(globe::patchesPerFaceSide(id.level));
        const double u = nadir.s * n - double(id.x), v = nadir.t * n - double(id.y);
        if (u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0)
            ceiling = std::max(ceiling, double(draw.maxHeight));
    }
    return ceiling;
}

double residentGroundHeight(const glm::dvec3& ecef, const io::PyramidLayout& layout,
                            const GlobeGroundLookup& lookup) {
    const globe::FacePoint nadir = globe::facePointOf(globe::Wgs84::upAt(ecef));
    std::optional<globe::GlobePatchId> deepest;
    const io::PatchInfo* deepestInfo = nullptr;
    glm::dvec2 uv(0.0);
    for (int level = 0; level <= io::kMaxGlobeFaceLevel; ++level) {
        const auto n = globe::patchesPerFaceSide(level);
        const double s = nadir.s * double(n), t = nadir.t * double(n);
        const globe::GlobePatchId id{
            nadir.face, level,
            std::clamp(static_cast<std::int64_t>(std::floor(s)), std::int64_t{0}, n - 1),
            std::clamp(static_cast<std::int64_t>(std::floor(t)), std::int64_t{0}, n - 1)};
        const io::PatchInfo* info = lookup.residentInfo(id);
        if (info == nullptr || !info->present) break;
        deepest = id;
        deepestInfo = info;
        uv = {s - double(id.x), t - double(id.y)};
    }
    if (!deepest) return 0.0;
    // Only a finest patch (no resident child) is replaced by native tiles: one that has
    // children is drawn from them or itself, never from a native tile.
    if (lookup.nativeTileUnder && lookup.cachedNativeTile && deepestInfo->presentChildren == 0) {
        if (const std::optional<Surface::NativeTilePoint> native = lookup.nativeTileUnder(
                globe::Wgs84::upAt(ecef), io::layoutPatchOf(*deepest).level)) {
            if (const io::PatchRecord* nativeTile = lookup.cachedNativeTile(native->tile)) {
                if (const std::optional<double> around =
                        highestSampleAround({native->u, native->v}, *nativeTile, layout))
                    return *around;
            }
        }
    }
    const io::PatchRecord* tile = lookup.cachedTile(*deepest);
    const std::optional<double> around =
        tile != nullptr ? highestSampleAround(uv, *tile, layout) : std::nullopt;
    return around.value_or(double(deepestInfo->maxHeight));
}

}  // namespace terrain::runtime
