// The virtual planet (VirtualPlanetPyramid): its Err(P) bounds the planet's continuous
// surface under every patch measured along the normal, as GlobePatchSurface draws it; shared
// edges and nested samples are bit-identical; it opens wherever a pyramid folder does.
#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/build/GlobePatchSurface.h"
#include "terrain/iothread/IoThread.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/source/SplitMix64.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace terrain::io {
namespace {

using globe::GlobePatchId;

VirtualPlanetPyramid openPlanet(const char* name) {
    Result<VirtualPlanetPyramid> planet = VirtualPlanetPyramid::open(name);
    EXPECT_TRUE(planet) << planet.error().message;
    return std::move(planet).value();
}

PatchRecord generate(const VirtualPlanetPyramid& planet, const GlobePatchId& id) {
    PatchRecord record;
    const Status generated = planet.generate(layoutPatchOf(id), record);
    EXPECT_TRUE(generated) << generated.error().message;
    return record;
}

// The patch under the summit ("go to the data") at a face level.
GlobePatchId patchAtSummit(const VirtualPlanetPyramid& planet, int level) {
    const ManifestGlobe& g = *planet.manifest().globe;
    const double lat = 0.5 * (g.south + g.north) * M_PI / 180.0;
    const double lon = 0.5 * (g.west + g.east) * M_PI / 180.0;
    const globe::FacePoint p = globe::facePointOf(
        {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)});
    const auto n = static_cast<double>(globe::patchesPerFaceSide(level));
    const auto index = [&](double s) {
        return std::clamp<std::int64_t>(static_cast<std::int64_t>(s * n), 0,
                                        globe::patchesPerFaceSide(level) - 1);
    };
    return {p.face, level, index(p.s), index(p.t)};
}

TEST(VirtualPlanetPyramid, ErrorBoundsTheContinuousSurfaceAlongTheNormal) {
    const VirtualPlanetPyramid planet = openPlanet("planet:seed=3,level=12");
    const int quads = planet.manifest().layout.patchQuads();
    std::vector<GlobePatchId> patches;
    for (int level = 0; level <= 12; ++level) patches.push_back(patchAtSummit(planet, level));
    // A cube corner, a pole (face 2's centre) and the antimeridian at coarse and fine levels.
    patches.push_back({0, 3, 7, 7});
    patches.push_back({2, 6, 31, 32});
    patches.push_back({3, 9, 255, 200});
    patches.push_back({5, 12, 0, 4095});
    detail::SplitMix64 rng(11);
    double worstRatio = 0.0;
    for (const GlobePatchId& id : patches) {
        const PatchRecord record = generate(planet, id);
        const GlobePatchSurface surface(id, quads, record.heights);
        double worst = 0.0;
        for (int k = 0; k < 4000; ++k) {
            const globe::FacePoint p = globe::patchPoint(id, rng.uniform(), rng.uniform());
            const glm::dvec3 n = globe::directionOf(p.face, p.s, p.t);
            const double h = planet.planet().heightAt(n.x, n.y, n.z);
            const auto [ad, bc] = surface.drawnHeights(n);
            worst = std::max({worst, std::abs(h - ad), std::abs(h - bc)});
        }
        EXPECT_LE(worst, record.info.error)
            << "patch " << id.face << "/" << id.level << "/" << id.x << "/" << id.y;
        worstRatio = std::max(worstRatio, worst / record.info.error);
    }
    // The bound is meant to be useful as well as true: the worst point found reaches a
    // sizeable part of it on some patch.
    EXPECT_GT(worstRatio, 0.1);
    RecordProperty("worst_measured_over_bound", std::to_string(worstRatio));
}

TEST(VirtualPlanetPyramid, SharedEdgesAndNestedSamplesAreBitIdentical) {
    const VirtualPlanetPyramid planet = openPlanet("planet:level=12");
    const int quads = planet.manifest().layout.patchQuads();
    const int tile = quads + 3;
    const auto at = [&](const PatchRecord& r, int i, int j) {
        return r.heights[static_cast<std::size_t>((j + 1) * tile + (i + 1))];
    };
    // Along the right edge of a patch on a cube edge, and its neighbour there (another face).
    for (const GlobePatchId& id :
         {GlobePatchId{0, 4, 15, 3}, GlobePatchId{1, 7, 127, 60}, GlobePatchId{4, 2, 1, 1}}) {
        const globe::PatchNeighbour right = globe::neighbourOf(id, globe::PatchSide::Right);
        const PatchRecord a = generate(planet, id);
        const PatchRecord b = generate(planet, right.id);
        for (int k = 0; k <= quads; ++k) {
            const int m = right.reversed ? quads - k : k;
            float other = 0.0f;
            switch (right.side) {
                case globe::PatchSide::Left:
                    other = at(b, 0, m);
                    break;
                case globe::PatchSide::Right:
                    other = at(b, quads, m);
                    break;
                case globe::PatchSide::Top:
                    other = at(b, m, 0);
                    break;
                case globe::PatchSide::Bottom:
                    other = at(b, m, quads);
                    break;
            }
            ASSERT_EQ(at(a, quads, k), other) << "sample " << k << " of face " << id.face;
        }
    }
    // A child's even samples are its parent's.
    const GlobePatchId parent = patchAtSummit(planet, 8);
    const PatchRecord p = generate(planet, parent);
    for (int c = 0; c < 4; ++c) {
        const GlobePatchId child{parent.face, 9, 2 * parent.x + (c & 1), 2 * parent.y + (c >> 1)};
        const PatchRecord r = generate(planet, child);
        for (int j = 0; j <= quads; j += 2)
            for (int i = 0; i <= quads; i += 2)
                ASSERT_EQ(at(r, i, j),
                          at(p, (c & 1) * quads / 2 + i / 2, (c >> 1) * quads / 2 + j / 2));
    }
}

TEST(VirtualPlanetPyramid, OpensWhereAFolderDoes) {
    Result<PyramidManifest> manifest = readManifest("planet:seed=2,level=5");
    ASSERT_TRUE(manifest) << manifest.error().message;
    ASSERT_TRUE(manifest.value().globe);
    EXPECT_EQ(manifest.value().globe->faceFinestLevel, 5);
    EXPECT_EQ(manifest.value().layout.finestLevel(), 5 + ManifestGlobe::kLevelOffset);

    Result<PyramidReader> reader = PyramidReader::open("planet:seed=2,level=5");
    ASSERT_TRUE(reader) << reader.error().message;
    const PatchId root = layoutPatchOf({1, 0, 0, 0});
    Result<PatchRecord> record = reader.value().readPatch(root);
    ASSERT_TRUE(record) << record.error().message;
    EXPECT_EQ(record.value().info.presentChildren, 0xF);
    EXPECT_GT(record.value().info.maxHeight, record.value().info.minHeight);
    Result<PatchRecord> finest = reader.value().readPatch(layoutPatchOf({1, 5, 3, 4}));
    ASSERT_TRUE(finest) << finest.error().message;
    EXPECT_EQ(finest.value().info.presentChildren, 0);
    EXPECT_LT(finest.value().info.error, record.value().info.error);
    EXPECT_FALSE(reader.value().readPatch(layoutPatchOf({1, 6, 0, 0})));  // below the finest

    // The I/O thread streams it like a folder.
    Result<std::unique_ptr<IoThread>> io = IoThread::start("planet:seed=2,level=5");
    ASSERT_TRUE(io) << io.error().message;
    ASSERT_TRUE(io.value()->submit(root, 1.0f));
    std::vector<Completion> done;
    while (done.empty()) {
        io.value()->waitForCompletion(std::chrono::milliseconds(1000));
        io.value()->poll(done);
    }
    ASSERT_EQ(done.front().status, CompletionStatus::Completed) << done.front().error;
    EXPECT_EQ(done.front().record.heights, record.value().heights);

    for (const char* bad :
         {"planet:level=29", "planet:colour=blue", "planet:seed", "planet:seed=x"}) {
        Result<PyramidManifest> refused = readManifest(bad);
        ASSERT_FALSE(refused) << bad;
        EXPECT_NE(refused.error().message.find(bad), std::string::npos) << refused.error().message;
    }
}

}  // namespace
}  // namespace terrain::io
