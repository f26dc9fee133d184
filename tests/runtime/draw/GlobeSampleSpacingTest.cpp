// The metres per sample a globe patch's instance record carries (placement4), which scale
// every slope of its shading normal: they must be the ground's own spacing, whichever side of
// the patch the camera is on. The record measures them at the patch's point nearest the
// camera, which lies on the patch's edge for every patch the camera is not above; a central
// difference clamped there measured half the spacing, so the patches ahead of the camera were
// shaded with twice their slopes and a seam ran along their edges (the main job's frame 240).
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/SurfacePlacement.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <string>

namespace terrain::runtime {
namespace {

constexpr int kQuads = 128;

glm::dvec3 groundAt(const globe::GlobePatchId& id, double u, double v) {
    const globe::FacePoint p = globe::patchPoint(id, u, v);
    return globe::Wgs84::pointAlongNormal(globe::directionOf(p.face, p.s, p.t), 0.0);
}

PatchInstance instanceOf(const globe::GlobePatchId& id, const glm::dvec3& camera) {
    PatchDraw draw;
    draw.id = draw.tileId = io::layoutPatchOf(id);
    return globePatchInstance(draw, camera, globe::Wgs84::upAt(camera), kQuads);
}

// Camera 2 km above patch `a`, a tenth of a patch from its edge shared with `b` (along s when
// `alongS`, else along t): `b`'s nearest point is on that edge.
void expectSpacingOfTheGround(const globe::GlobePatchId& a, bool alongS, const std::string& where) {
    const globe::GlobePatchId b{a.face, a.level, a.x + (alongS ? 1 : 0), a.y + (alongS ? 0 : 1)};
    const glm::dvec3 nearEdge = alongS ? groundAt(a, 0.9, 0.5) : groundAt(a, 0.5, 0.9);
    const glm::dvec3 camera = nearEdge + 2000.0 * globe::Wgs84::upAt(nearEdge);
    const PatchInstance ia = instanceOf(a, camera), ib = instanceOf(b, camera);
    // b's nearest point: on the shared edge (u = 0 along s, v = 0 along t).
    EXPECT_EQ(alongS ? ib.placement0[1] : ib.placement0[2], 0.0f) << where;
    // One sample of b across the shared edge, measured on the ground: its spacing there.
    const double u = alongS ? 0.0 : ib.placement0[1], v = alongS ? ib.placement0[2] : 0.0;
    const double step = 1.0 / kQuads;
    const double ground = glm::distance(groundAt(b, u, v),
                                        alongS ? groundAt(b, u + step, v) : groundAt(b, u, v + step));
    const int axis = alongS ? 0 : 1;
    EXPECT_NEAR(ib.placement4[axis], ground, 1e-3 * ground) << where << ": the patch ahead";
    EXPECT_NEAR(ia.placement4[axis], ib.placement4[axis], 1e-2 * ground)
        << where << ": two neighbours of one level must share their spacing where they meet";
}

TEST(GlobeSampleSpacingTest, IsTheGroundsOwnOnEveryPatchAroundTheCamera) {
    for (const int level : {6, 10, 14}) {
        const std::int64_t n = globe::patchesPerFaceSide(level);
        for (const int face : {0, 3, 5}) {
            const globe::GlobePatchId a{face, level, n / 3, n / 2};
            const std::string where =
                "face " + std::to_string(face) + ", level " + std::to_string(level);
            expectSpacingOfTheGround(a, true, where + ", along s");
            expectSpacingOfTheGround(a, false, where + ", along t");
        }
    }
}

}  // namespace
}  // namespace terrain::runtime
