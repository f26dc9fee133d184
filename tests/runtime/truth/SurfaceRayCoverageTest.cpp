// everyTriangulationCovers: a pixel's ray is covered by the full-resolution surface whatever
// diagonal splits each cell only if some cell is hit along both of its diagonals. Checked on a
// flat DEM (any ray that goes down meets it; one that goes up does not) and on one needle,
// whose cell is a ridge along one diagonal and a flat half along the other; and lowered by
// the LOD's allowed error, a ray that only grazes the ground is no longer covered.
#include "AccuracyScenes.h"
#include "TempFolder.h"
#include "terrain/runtime/SurfaceRayCoverage.h"

#include <gtest/gtest.h>

namespace terrain::test {
namespace {

constexpr std::int64_t kSide = 9;

struct Surface {
    TempFolder folder;
    std::unique_ptr<runtime::FullResolutionSurface> surface;

    explicit Surface(FunctionDem::Height height) {
        FunctionDem dem(kSide, kSide, 1.0, std::move(height), false);
        const std::filesystem::path pyramid = buildScenePyramid(dem, folder, "ray", 9, 4);
        auto opened = runtime::FullResolutionSurface::open(pyramid);
        EXPECT_TRUE(opened) << opened.error().message;
        if (opened) {
            surface = std::make_unique<runtime::FullResolutionSurface>(std::move(opened).value());
        }
    }
    /// World point of sample coordinates (column, row) at height z.
    glm::dvec3 at(double column, double row, double z) const {
        return {surface->geometry().worldOfSample(column, row), z};
    }
    bool covers(const glm::dvec3& from, const glm::dvec3& to, double lowerPerMetre = 0.0) {
        auto covered = runtime::everyTriangulationCovers(*surface, from, to - from, lowerPerMetre);
        EXPECT_TRUE(covered) << covered.error().message;
        return covered && covered.value();
    }
};

TEST(SurfaceRayCoverage, FlatGroundIsCoveredFromAboveOnly) {
    Surface flat([](std::int64_t, std::int64_t) { return 10.0F; });
    ASSERT_TRUE(flat.surface);
    EXPECT_TRUE(flat.covers(flat.at(4.3, 4.6, 50.0), flat.at(4.3, 4.6, 0.0)));    // straight down
    EXPECT_TRUE(flat.covers(flat.at(-20.0, 3.0, 50.0), flat.at(6.0, 5.0, 0.0)));  // slanting in
    EXPECT_FALSE(flat.covers(flat.at(4.3, 4.6, 50.0), flat.at(4.0, 4.0, 90.0)));  // upwards
    EXPECT_FALSE(flat.covers(flat.at(4.0, 4.0, 5.0), flat.at(6.0, 7.0, 5.0)));    // below it
    // Outside the DEM, going away from it.
    EXPECT_FALSE(flat.covers(flat.at(-5.0, 4.0, 50.0), flat.at(-9.0, 4.0, 0.0)));
}

TEST(SurfaceRayCoverage, ANeedleCellCoversOnlyWhereBothDiagonalsRise) {
    // Sample (4, 4) is 1,000 m high, all others 0. Along one diagonal its cell (4, 4)–(5, 5)
    // is a ridge from the tip to (5, 5); along the other, the half nearer (5, 5) is flat.
    Surface needle(
        [](std::int64_t x, std::int64_t y) { return x == 4 && y == 4 ? 1000.0F : 0.0F; });
    ASSERT_TRUE(needle.surface);
    // Horizontal rays at 100 m along the line column + row = constant: only this cell rises
    // above 100 m on it. Through (4.8, 4.8): 200 m on the ridge, 0 on the flat half.
    EXPECT_FALSE(needle.covers(needle.at(1.8, 7.8, 100.0), needle.at(4.8, 4.8, 100.0)));
    // Through (4.2, 4.2): 800 m on the ridge and 600 m on the other diagonal's slope.
    EXPECT_TRUE(needle.covers(needle.at(1.2, 7.2, 100.0), needle.at(4.2, 4.2, 100.0)));
    // Any ray that goes down meets the ground, needle or not.
    EXPECT_TRUE(needle.covers(needle.at(4.8, 4.8, 2000.0), needle.at(4.8, 4.8, 0.0)));
}

TEST(SurfaceRayCoverage, LoweredByTheAllowedErrorAGrazingRayIsNotCovered) {
    Surface flat([](std::int64_t, std::int64_t) { return 10.0F; });
    ASSERT_TRUE(flat.surface);
    // Descending 2.1 m over 8 m of ground, the ray meets the 10 m plane 0.4 m before the
    // DEM's far edge. Lowered by 5 cm a metre (about 0.4 m there), the plane lets it
    // through: a LOD within that error may leave its pixel clear.
    const glm::dvec3 from = flat.at(0.0, 4.0, 12.0), to = flat.at(8.0, 4.0, 9.9);
    EXPECT_TRUE(flat.covers(from, to));
    EXPECT_FALSE(flat.covers(from, to, 0.05));
    // A ray that meets the ground squarely is covered however the ground is lowered that much.
    EXPECT_TRUE(flat.covers(flat.at(4.3, 4.6, 50.0), flat.at(4.3, 4.6, 0.0), 0.05));
    EXPECT_TRUE(flat.covers(flat.at(-20.0, 3.0, 50.0), flat.at(6.0, 5.0, 0.0), 0.05));
}

}  // namespace
}  // namespace terrain::test
