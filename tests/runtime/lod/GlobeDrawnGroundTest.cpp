// The ground under the globe viewer's camera, from the resident patches and the tiles in the
// CPU cache: the highest of the four samples around the nadir in the deepest resident patch
// (the drawn surface between them lies at or below it), not that patch's highest point;
// its highest point when its tile is not at hand or not finite; 0 (the bare ellipsoid)
// with nothing resident; below sea level where the ground is; found from under the ground;
// where a native tile replaces the finest patch near the ground, that tile's samples.
#include "terrain/runtime/GlobeDrawnGround.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/NativeTiles.h"
#include "terrain/runtime/NativeOwnership.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <vector>

namespace terrain::runtime {
namespace {

constexpr float kSpike = 3000.0f;
const globe::GlobePatchId kPatch{2, 5, 7, 12};

io::PyramidLayout layout() {
    auto made = io::globeLayout(10);
    EXPECT_TRUE(made);
    return made.value();
}

// Heights rise gently along both tile axes, with one spike, the patch's highest point.
io::PatchRecord tile(const io::PyramidLayout& l) {
    io::PatchRecord record;
    const int side = l.tileSamples();
    record.heights.resize(static_cast<std::size_t>(side * side));
    for (int row = 0; row < side; ++row)
        for (int column = 0; column < side; ++column)
            record.heights[static_cast<std::size_t>(row * side + column)] =
                100.0f + 0.5f * float(column) + 0.25f * float(row);
    record.heights[static_cast<std::size_t>(20 * side + 100)] = kSpike;
    return record;
}

double heightAt(int column, int row) { return 100.0 + 0.5 * column + 0.25 * row; }

// Resident: kPatch and its ancestors down to `deepestLevel`, each with maxHeight `top` and
// kPatch's level with `tile` in the CPU cache (when not null).
struct Streaming {
    std::map<std::tuple<int, int, std::int64_t, std::int64_t>, io::PatchInfo> resident;
    const io::PatchRecord* tile = nullptr;

    Streaming(int deepestLevel, float top) {
        for (int level = 0; level <= deepestLevel; ++level) {
            io::PatchInfo info;
            info.present = true;
            info.maxHeight = top;
            const int shift = kPatch.level - level;
            resident[{kPatch.face, level, kPatch.x >> shift, kPatch.y >> shift}] = info;
        }
    }
    GlobeGroundLookup lookup() const {
        return {.residentInfo = [this](const globe::GlobePatchId& id) -> const io::PatchInfo* {
                    const auto found = resident.find({id.face, id.level, id.x, id.y});
                    return found == resident.end() ? nullptr : &found->second;
                },
                .cachedTile = [this](const globe::GlobePatchId& id) -> const io::PatchRecord* {
                    return id.level == kPatch.level && id.x == kPatch.x && id.y == kPatch.y
                               ? tile
                               : nullptr;
                },
                .nativeTileUnder = {},
                .cachedNativeTile = {}};
    }
};

// `heightM` above patch coordinates (u, v) of `id`.
glm::dvec3 at(const globe::GlobePatchId& id, double u, double v, double heightM) {
    const globe::FacePoint p = globe::patchPoint(id, u, v);
    return globe::Wgs84::pointAlongNormal(globe::directionOf(p.face, p.s, p.t), heightM);
}

TEST(GlobeDrawnGround, IsTheHighestOfTheFourSamplesAroundTheNadirNotThePatchsTop) {
    const io::PyramidLayout l = layout();
    const io::PatchRecord record = tile(l);
    Streaming streaming(kPatch.level, kSpike);
    streaming.tile = &record;
    const double quads = l.patchQuads();
    // Patch sample (38.4, 76.8) is tile sample (39.4, 77.8): columns 39, 40, rows 77, 78.
    const double u = 38.4 / quads, v = 76.8 / quads;
    EXPECT_NEAR(residentGroundHeight(at(kPatch, u, v, 500.0), l, streaming.lookup()),
                heightAt(40, 78), 1e-3);
    // From under the ground (a jump to 1 m above the ellipsoid under a mountain): the same.
    EXPECT_NEAR(residentGroundHeight(at(kPatch, u, v, 1.0), l, streaming.lookup()),
                heightAt(40, 78), 1e-3);
    // Next to the spike the spike is the ground.
    EXPECT_DOUBLE_EQ(
        residentGroundHeight(at(kPatch, 99.5 / quads, 19.5 / quads, 5000.0), l, streaming.lookup()),
        kSpike);
    // Its tile no longer in the CPU cache: the patch's highest point.
    streaming.tile = nullptr;
    EXPECT_DOUBLE_EQ(residentGroundHeight(at(kPatch, u, v, 500.0), l, streaming.lookup()), kSpike);
}

TEST(GlobeDrawnGround, IsWhatTheDeepestResidentPatchHoldsAndTheEllipsoidWithoutOne) {
    const io::PyramidLayout l = layout();
    const io::PatchRecord record = tile(l);
    // Resident down to level 3 only: kPatch's tile in the cache is not what is drawn.
    Streaming coarse(3, 4500.0f);
    coarse.tile = &record;
    EXPECT_DOUBLE_EQ(residentGroundHeight(at(kPatch, 0.5, 0.5, 10.0), l, coarse.lookup()), 4500.0);
    // A nadir on another face, where nothing is resident: the bare ellipsoid.
    EXPECT_DOUBLE_EQ(residentGroundHeight(at({0, 5, 7, 12}, 0.5, 0.5, 10.0), l, coarse.lookup()),
                     0.0);
}

TEST(GlobeDrawnGround, BelowSeaLevelIsBelowTheEllipsoidAndNaNIsNotGround) {
    const io::PyramidLayout l = layout();
    io::PatchRecord deep = tile(l);
    for (float& h : deep.heights) h = -400.0f;
    Streaming streaming(kPatch.level, -400.0f);
    streaming.tile = &deep;
    const glm::dvec3 camera = at(kPatch, 0.5, 0.5, -390.0);
    EXPECT_DOUBLE_EQ(residentGroundHeight(camera, l, streaming.lookup()), -400.0);
    // A sample that is not finite: the patch's highest point, never NaN.
    for (float& h : deep.heights) h = std::numeric_limits<float>::quiet_NaN();
    Streaming damaged(kPatch.level, 250.0f);
    damaged.tile = &deep;
    EXPECT_DOUBLE_EQ(residentGroundHeight(camera, l, damaged.lookup()), 250.0);
}

// Native leaves (docs/globe.md): where the LOD draws a native tile in place of the finest face
// patch, the ground is the highest of that tile's four samples around the nadir (its own
// tile coordinates), not the face grid's resampling; the face grid's where the tile is not in
// the CPU cache, where the patch has finer data (no native tile replaces it) or where no grid
// serves the patch's level.
TEST(GlobeDrawnGround, IsTheNativeTilesWhereOneReplacesTheFinestPatch) {
    const io::PyramidLayout l = layout();
    const io::PatchRecord face = tile(l);
    io::PatchRecord native = tile(l);
    for (float& h : native.heights) h += 40.0f;  // the source's own surface, 40 m higher here
    const io::PatchId nativeId = io::nativeTileId(0, 3, 9);
    Streaming streaming(kPatch.level, kSpike);
    streaming.tile = &face;
    const double quads = l.patchQuads();
    const double u = 38.4 / quads, v = 76.8 / quads;
    const glm::dvec3 camera = at(kPatch, u, v, 500.0);
    int askedLevel = -1;
    const io::PatchRecord* cachedNative = &native;
    GlobeGroundLookup lookup = streaming.lookup();
    // A fake grid: the nadir at the native tile's samples (10.2, 60.7), whose four around are
    // columns 11, 12 and rows 61, 62 of the tile (its apron first).
    const int patchLevel = io::layoutPatchOf(kPatch).level;
    lookup.nativeTileUnder = [&](const glm::dvec3&,
                                 int level) -> std::optional<Surface::NativeTilePoint> {
        askedLevel = level;
        if (level < patchLevel) return std::nullopt;  // too fine for coarser patches
        return Surface::NativeTilePoint{nativeId, 10.2 / quads, 60.7 / quads};
    };
    lookup.cachedNativeTile = [&](const io::PatchId& id) {
        return id == nativeId ? cachedNative : nullptr;
    };
    EXPECT_NEAR(residentGroundHeight(camera, l, lookup), heightAt(12, 62) + 40.0, 1e-3);
    EXPECT_EQ(askedLevel, patchLevel);
    // Not in the CPU cache: the face grid's.
    cachedNative = nullptr;
    EXPECT_NEAR(residentGroundHeight(camera, l, lookup), heightAt(40, 78), 1e-3);
    cachedNative = &native;
    // The deepest resident patch has finer data (its children not yet resident): it is drawn
    // itself, never replaced by a native tile.
    streaming.resident[{kPatch.face, kPatch.level, kPatch.x, kPatch.y}].presentChildren = 0b1111;
    EXPECT_NEAR(residentGroundHeight(camera, l, lookup), heightAt(40, 78), 1e-3);
    // Resident down to a coarser level only, which no grid serves: that patch's highest point.
    Streaming coarse(3, 4500.0f);
    GlobeGroundLookup coarseLookup = coarse.lookup();
    coarseLookup.nativeTileUnder = lookup.nativeTileUnder;
    coarseLookup.cachedNativeTile = lookup.cachedNativeTile;
    EXPECT_DOUBLE_EQ(residentGroundHeight(camera, l, coarseLookup), 4500.0);
}

// The stress flight's ground where no patch can be read: the highest point of what is drawn
// over the nadir. A native tile counts only over the ground it owns (NativeOwnership.h), the
// face patches it stands for, not wherever its outline reaches; one that owns all it covers
// counts everywhere.
TEST(GlobeDrawnGround, TheCeilingTakesANativeTileOnlyOverTheGroundItOwns) {
    const glm::dvec3 camera = at(kPatch, 0.5, 0.5, 5000.0);
    io::PatchInfo low;
    low.maxHeight = 300.0f;
    io::PatchInfo high;
    high.maxHeight = 2000.0f;
    const globe::GlobePatchId east{kPatch.face, kPatch.level, kPatch.x + 1, kPatch.y};
    std::vector<PatchDraw> draws{PatchDraw::ofTile(io::layoutPatchOf(kPatch), 0, low),
                                 PatchDraw::ofTile(io::nativeTileId(0, 3, 4), 1, high)};
    const io::PatchId holders[] = {io::layoutPatchOf(east), io::layoutPatchOf(kPatch)};
    assignNativeOwnership(draws[1], std::span(holders, 1));  // its patch east of the nadir's
    EXPECT_DOUBLE_EQ(drawnGroundCeiling(draws, camera), 300.0);
    assignNativeOwnership(draws[1], holders);  // and the nadir's
    EXPECT_DOUBLE_EQ(drawnGroundCeiling(draws, camera), 2000.0);
    assignNativeOwnership(draws[1], std::span(holders, 1));
    draws[1].nativeCells = 0;  // owns all it covers (its patches on two faces): anywhere
    EXPECT_DOUBLE_EQ(drawnGroundCeiling(draws, camera), 2000.0);
}

}  // namespace
}  // namespace terrain::runtime
