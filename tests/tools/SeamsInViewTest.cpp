// SeamsInView (terrain-bench): a frame shows a source seam when a drawn pixel lies in the band
// inside the source's edge where it is blended into the source beneath; then its slope and
// its source's 99th-percentile slope are the frame's. Straight-down views over a made-up
// manifest, each pixel drawn at the camera's height below it (a plane at that distance,
// within metres of the ground for a narrow view). No GL, no file.
#include "SeamsInView.h"

#include "terrain/runtime/GlobeCamera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace terrain::tools {
namespace {

constexpr int kSide = 32;
constexpr double kHeightM = 2000.0;

io::PyramidManifest composite() {
    io::PyramidManifest m;
    m.globe = io::ManifestGlobe{};
    // A 1° tile over a global grid, blended across 3 to 5 km inside its edge.
    m.globe->sources = {{"tile.tif", 10.0, 45.0, 11.0, 46.0, {}},
                        {"global.nc", -180, -90, 180, 90, {}}};
    io::ManifestSeam seam;
    seam.input = "tile.tif";
    seam.seamSlope = 0.3;
    seam.sourceSlopeP99 = 0.8;
    seam.bandMetres = {3000.0, 5000.0};
    m.globe->seams = {seam};
    return m;
}

SeamsSeen seenFrom(double latitudeDeg, double longitudeDeg, float depthScale = 1.0f) {
    runtime::Camera camera;
    camera.viewportWidth = kSide;
    camera.viewportHeight = kSide;
    camera.fovY = 2.0 * std::numbers::pi / 180.0;  // 70 m across at 2 km
    runtime::placeOnGlobe(camera, {{latitudeDeg, longitudeDeg, kHeightM}, 0.0, -90.0});
    const std::vector<float> depth(kSide * kSide,
                                   depthScale * static_cast<float>(camera.nearPlane / kHeightM));
    return seamsInView(composite(), camera, depth);
}

TEST(SeamsInView, ASeamIsSeenWhereItsBandIsDrawn) {
    // 0.02° (2.2 km) inside the tile's southern edge: in the band.
    const SeamsSeen inBand = seenFrom(45.02, 10.5);
    EXPECT_EQ(inBand.seams, 1);
    EXPECT_EQ(inBand.seamSlope, 0.3);
    EXPECT_EQ(inBand.sourceSlopeP99, 0.8);
    // Near the western edge too (0.04° of longitude at 45.5° N is 3.1 km).
    EXPECT_EQ(seenFrom(45.5, 10.04).seams, 1);
    // The tile's middle, 55 km from any edge; outside the tile; nothing drawn.
    for (const SeamsSeen& none :
         {seenFrom(45.5, 10.5), seenFrom(44.98, 10.5), seenFrom(45.02, 10.5, 0.0f)}) {
        EXPECT_EQ(none.seams, 0);
        EXPECT_TRUE(std::isnan(none.seamSlope));
    }
    // A plane has no seam.
    runtime::Camera camera;
    camera.viewportWidth = camera.viewportHeight = kSide;
    EXPECT_EQ(
        seamsInView(io::PyramidManifest{}, camera, std::vector<float>(kSide * kSide, 1.0f)).seams,
        0);
}

}  // namespace
}  // namespace terrain::tools
