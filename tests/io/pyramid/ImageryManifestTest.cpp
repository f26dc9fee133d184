// The imagery vocabulary (issue 47): layers recorded in the manifest and checked, and where
// an imagery tile's texels lie on the terrain's tiling (ImageryTile.h).
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <gtest/gtest.h>

namespace terrain::io {
namespace {

PyramidManifest planarWithLayers() {
    PyramidManifest m = PyramidManifest::forLayout(PyramidLayout::create(1025, 1025).value());
    m.imagery.push_back({.name = "photo",
                         .kind = std::string(ManifestImageryLayer::kStoredKind),
                         .folder = "imagery/photo",
                         .input = "photo.tif",
                         .codec = "webp",
                         .coarsestLevel = 0,
                         .finestLevel = 6,
                         .opacity = 0.75});
    m.imagery.push_back({.name = "roads",
                         .kind = std::string(ManifestImageryLayer::kStoredKind),
                         .folder = "imagery/roads",
                         .input = "roads.png",
                         .codec = "webp",
                         .coarsestLevel = 0,
                         .finestLevel = 3,
                         .opacity = 1.0});
    return m;
}

TEST(ImageryManifest, LayersRoundTripInOrder) {
    const PyramidManifest m = planarWithLayers();
    const auto back = fromJson(toJson(m), "test");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back.value(), m);
    ASSERT_EQ(back.value().imagery.size(), 2u);
    EXPECT_EQ(back.value().imagery[1].name, "roads");
    // A manifest without layers writes no "imagery" key: older readers read it as before.
    PyramidManifest plain = m;
    plain.imagery.clear();
    EXPECT_EQ(toJson(plain).find("imagery"), std::string::npos);
}

TEST(ImageryManifest, BadLayersAreRefusedByName) {
    const auto refused = [](PyramidManifest m, const std::string& expected) {
        const auto back = fromJson(toJson(m), "m.json");
        ASSERT_FALSE(back.ok()) << expected;
        EXPECT_NE(back.error().message.find(expected), std::string::npos)
            << back.error().message;
        EXPECT_NE(back.error().message.find("m.json"), std::string::npos);
    };
    PyramidManifest twice = planarWithLayers();
    twice.imagery[1].name = "photo";
    refused(twice, "also imagery[0]'s");
    PyramidManifest opaque = planarWithLayers();
    opaque.imagery[0].opacity = 1.5;
    refused(opaque, "opacity 1.5");
    PyramidManifest outside = planarWithLayers();
    outside.imagery[0].folder = "../elsewhere";
    refused(outside, "inside the pyramid");
    PyramidManifest deep = planarWithLayers();
    deep.imagery[0].finestLevel = deep.layout.finestLevel() + 17;
    refused(deep, "levels 0");
    PyramidManifest planet = planarWithLayers();
    planet.imagery[0].kind = std::string(ManifestImageryLayer::kPlanetKind);
    refused(planet, "virtual planet");
}

TEST(ImageryTexels, PlanarTexelCentresContinueAcrossPatchesAndLevels) {
    const PyramidLayout layout = PyramidLayout::create(1025, 1025).value();  // finest level 3
    // The interior's first and last texel edges are the patch's first and last samples.
    const PlanarSamplePoint first = planarImageryPoint(layout, {3, 2, 1}, 0.0, 0.0);
    EXPECT_DOUBLE_EQ(first.column, 256.0);
    EXPECT_DOUBLE_EQ(first.row, 128.0);
    EXPECT_DOUBLE_EQ(imageryPatchLocal(kImageryBorderTexels), 0.0);
    EXPECT_DOUBLE_EQ(imageryPatchLocal(kImageryTileTexels - kImageryBorderTexels), 1.0);
    // Past the finest level a patch spans a fraction of the DEM's samples per texel, and a
    // child's corner is its parent's centre.
    const PlanarSamplePoint parent = planarImageryPoint(layout, {5, 3, 3}, 0.5, 0.5);
    const PlanarSamplePoint child = planarImageryPoint(layout, {6, 7, 7}, 0.0, 0.0);
    EXPECT_DOUBLE_EQ(parent.column, child.column);
    EXPECT_DOUBLE_EQ(parent.row, child.row);
    // A border texel of one patch is an interior texel's centre of its neighbour.
    const double border = imageryPatchLocal(kImageryTileTexels - 2 + 0.5);
    const double inNeighbour = imageryPatchLocal(kImageryBorderTexels + 2 + 0.5);
    EXPECT_DOUBLE_EQ(planarImageryPoint(layout, {2, 0, 0}, border, 0.5).column,
                     planarImageryPoint(layout, {2, 1, 0}, inNeighbour, 0.5).column);
}

TEST(ImageryTexels, GlobeTexelsAreTheHeightsFacePoints) {
    // Face 2, face level 4, patch (5, 9): layout x = 2 · 16 + 5.
    const PatchId id{ManifestGlobe::kLevelOffset + 4, 2 * 16 + 5, 9};
    const globe::FacePoint corner = globeImageryPoint(id, 0.0, 1.0);
    EXPECT_EQ(corner.face, 2);
    EXPECT_DOUBLE_EQ(corner.s, 5.0 / 16.0);
    EXPECT_DOUBLE_EQ(corner.t, 10.0 / 16.0);
    EXPECT_EQ(globePatchOf(id).face, 2);
    EXPECT_EQ(globePatchOf(id).x, 5);
    // The border of a patch on the face's edge lies beyond it (directionOf continues there).
    EXPECT_LT(globeImageryPoint({ManifestGlobe::kLevelOffset, 0, 0}, -0.01, 0.5).s, 0.0);
}

}  // namespace
}  // namespace terrain::io
