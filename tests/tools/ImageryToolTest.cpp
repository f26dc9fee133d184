// terrain-imagery as a user runs it (issue 47, docs/imagery.md): Blue Marble over a globe
// pyramid of ETOPO with the Boston inset above it, the Puget Sound texture laid on its DEM's
// extent, and bad input refused with a message naming the file, exit status 1, nothing
// written (no layer folder, the manifest as it was). Needs ../shared/data (skips without).
#include "SharedData.h"

#include "terrain/pyramid/ImageryTileReader.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;

struct ToolRun {
    int status = -1;
    std::string output;  // stdout and stderr
};

ToolRun run(const std::string& program, const std::string& arguments) {
    ToolRun r;
    const fs::path err =
        fs::temp_directory_path() / ("terrain-imagery-test-" + std::to_string(::getpid()) + ".err");
    FILE* pipe = ::popen((program + " " + arguments + " 2>" + err.string()).c_str(), "r");
    if (pipe == nullptr) return r;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    const int status = ::pclose(pipe);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(err);
    r.output += std::string(std::istreambuf_iterator<char>(in), {});
    fs::remove(err);
    return r;
}

std::string manifestText(const fs::path& pyramid) {
    std::ifstream in(pyramid / "manifest.json");
    return {std::istreambuf_iterator<char>(in), {}};
}

class ImageryTool : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        s_dir = fs::temp_directory_path() / ("terrain-imagery-" + std::to_string(::getpid()));
        fs::remove_all(s_dir);
        fs::create_directories(s_dir);
    }
    static void TearDownTestSuite() { fs::remove_all(s_dir); }

    // Builds a pyramid of `dem` once per suite.
    static fs::path pyramidOf(const fs::path& dem, const std::string& name,
                              const std::string& flags) {
        const fs::path out = s_dir / name;
        if (!fs::exists(out / "manifest.json")) {
            const ToolRun built = run(TERRAIN_BUILD, "-q " + flags + " " + dem.string() + " -o " +
                                                         out.string() + " --overwrite");
            EXPECT_EQ(built.status, 0) << built.output;
        }
        return out;
    }

    static void expectRefused(const ToolRun& r, const fs::path& pyramid,
                              const std::string& manifestBefore, const std::string& message,
                              const std::string& file) {
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
        EXPECT_EQ(manifestText(pyramid), manifestBefore);
        // Nothing half-written: no layer folder, no temporary one.
        if (!fs::exists(pyramid / "imagery")) return;
        for (const auto& entry : fs::directory_iterator(pyramid / "imagery")) {
            const std::string name = entry.path().filename().string();
            EXPECT_TRUE(name.find(".tmp-") == std::string::npos &&
                        name.find(".old-") == std::string::npos)
                << "left behind: " << entry.path();
        }
    }

    static inline fs::path s_dir;
};

TEST_F(ImageryTool, BlueMarbleOverTheGlobeWithBostonAbove) {
    TERRAIN_SHARED_DATA_OR_SKIP(etopo, "etopo20_global.nc");
    TERRAIN_SHARED_DATA_OR_SKIP(blueMarble, "imagery/bluemarble_world_2048.tif");
    TERRAIN_SHARED_DATA_OR_SKIP(boston, "imagery/boston_inset_wgs84.tif");
    const fs::path globe = pyramidOf(etopo, "globe", "--globe");
    const ToolRun wholeEarth =
        run(TERRAIN_IMAGERY, globe.string() + " " + blueMarble.string() + " --json --replace");
    ASSERT_EQ(wholeEarth.status, 0) << wholeEarth.output;
    const ToolRun inset = run(TERRAIN_IMAGERY, globe.string() + " " + boston.string() +
                                                   " --name boston --opacity 0.9 --replace");
    ASSERT_EQ(inset.status, 0) << inset.output;
    const auto manifest = readManifest(globe);
    ASSERT_TRUE(manifest.ok()) << manifest.error().message;
    ASSERT_EQ(manifest.value().imagery.size(), 2u);
    const ManifestImageryLayer& bottom = manifest.value().imagery[0];
    const ManifestImageryLayer& top = manifest.value().imagery[1];
    EXPECT_EQ(bottom.name, "bluemarble_world_2048");
    EXPECT_EQ(top.name, "boston");
    EXPECT_DOUBLE_EQ(top.opacity, 0.9);
    // 2048 pixels around the Earth: 0.18° pixels, 512 a face where face level 1 has 496
    // interior texels (0.186°, within --finest-texel-pixels' default 1.1 of the pixel; the
    // level below would store 4× the texels for 3 % of resolution).
    EXPECT_EQ(bottom.finestLevel, ManifestGlobe::kLevelOffset + 1);
    EXPECT_EQ(top.finestLevel, ManifestGlobe::kLevelOffset + 8);
    // Blue Marble covers the Earth: every tile of every level opaque, the polar faces too,
    // whose texels take every longitude (a tile unwrapped around its centre left a line of
    // half-transparent texels along the meridian opposite the centre's: a streak of the tint
    // from the pole to the face's corner).
    auto world = openImageryTiles(globe, manifest.value(), bottom);
    ASSERT_TRUE(world.ok()) << world.error().message;
    ImageryTile tile;
    for (int level = bottom.coarsestLevel; level <= bottom.finestLevel; ++level) {
        const std::int64_t perFace = std::int64_t{1} << (level - ManifestGlobe::kLevelOffset);
        for (std::int64_t y = 0; y < perFace; ++y)
            for (std::int64_t x = 0; x < 6 * perFace; ++x) {
                ASSERT_TRUE(world.value()->readTile({level, x, y}, tile).ok());
                EXPECT_TRUE(tile.info.present && tile.info.opaque)
                    << "tile " << level << "/" << x << "/" << y;
            }
    }
    auto tiles = openImageryTiles(globe, manifest.value(), top);
    ASSERT_TRUE(tiles.ok()) << tiles.error().message;
    for (std::int64_t face = 0; face < 6; ++face) {  // every root, transparent away from Boston
        ASSERT_TRUE(tiles.value()->readTile({ManifestGlobe::kLevelOffset, face, 0}, tile).ok());
        EXPECT_TRUE(tile.info.present);
        EXPECT_FALSE(tile.info.opaque);
    }
    const ToolRun verified = run(TERRAIN_INSPECT, globe.string() + " --verify");
    EXPECT_EQ(verified.status, 0) << verified.output;
    EXPECT_NE(verified.output.find("boston"), std::string::npos) << verified.output;
    // Built again under the same name: refused without --replace.
    const std::string before = manifestText(globe);
    const ToolRun again =
        run(TERRAIN_IMAGERY, globe.string() + " " + boston.string() + " --name boston");
    expectRefused(again, globe, before, "already has an imagery layer \"boston\"", globe.string());
}

TEST_F(ImageryTool, PugetSoundTextureOnItsDemExtent) {
    TERRAIN_SHARED_DATA_OR_SKIP(dem, "puget_sound_1k.png");
    TERRAIN_SHARED_DATA_OR_SKIP(texture, "puget_sound_texture_1k.png");
    const fs::path puget = pyramidOf(dem, "puget", "--vertical-scale 0.1 --spacing 10");
    const std::string before = manifestText(puget);
    // Without a georeference, only with --dem-extent.
    expectRefused(run(TERRAIN_IMAGERY, puget.string() + " " + texture.string()), puget, before,
                  "has no georeference", texture.string());
    const ToolRun laid =
        run(TERRAIN_IMAGERY, puget.string() + " " + texture.string() + " --dem-extent --lossless");
    ASSERT_EQ(laid.status, 0) << laid.output;
    const auto manifest = readManifest(puget);
    ASSERT_TRUE(manifest.ok());
    ASSERT_EQ(manifest.value().imagery.size(), 1u);
    // 1024 pixels over 1024 sample spacings: texels of 1.03 samples, a level above the DEM's
    // finest (whose texels of 0.52 samples would store 4× the texels for 3 % of resolution).
    EXPECT_EQ(manifest.value().imagery[0].finestLevel, manifest.value().layout.finestLevel() - 1);
    const ToolRun verified = run(TERRAIN_INSPECT, puget.string() + " --verify --json");
    EXPECT_EQ(verified.status, 0) << verified.output;
    EXPECT_NE(verified.output.find("\"imagery\""), std::string::npos);
}

TEST_F(ImageryTool, AFifthLayerIsRefused) {
    // One draw composites four layers: a fifth would be stored and never drawn.
    TERRAIN_SHARED_DATA_OR_SKIP(dem, "puget_sound_1k.png");
    TERRAIN_SHARED_DATA_OR_SKIP(texture, "puget_sound_texture_1k.png");
    const fs::path puget = pyramidOf(dem, "puget-layers", "--vertical-scale 0.1 --spacing 10");
    for (const char* name : {"a", "b", "c", "d"}) {
        const ToolRun laid = run(TERRAIN_IMAGERY, puget.string() + " " + texture.string() +
                                                      " --dem-extent --name " + name);
        ASSERT_EQ(laid.status, 0) << laid.output;
    }
    const std::string before = manifestText(puget);
    expectRefused(
        run(TERRAIN_IMAGERY, puget.string() + " " + texture.string() + " --dem-extent --name e"),
        puget, before, "already has 4 imagery layers", puget.string());
    // Rebuilding one of the four is still possible.
    const ToolRun replaced = run(TERRAIN_IMAGERY, puget.string() + " " + texture.string() +
                                                      " --dem-extent --name b --replace");
    EXPECT_EQ(replaced.status, 0) << replaced.output;
}

TEST_F(ImageryTool, BadInputIsRefusedAndNothingWritten) {
    TERRAIN_SHARED_DATA_OR_SKIP(luxembourg, "luxembourg_elev_30s.tif");
    TERRAIN_SHARED_DATA_OR_SKIP(rainier, "srtm3_n46w122_rainier.tif");
    TERRAIN_SHARED_DATA_OR_SKIP(boston, "imagery/boston_inset_wgs84.tif");
    TERRAIN_SHARED_DATA_OR_SKIP(blueMarble, "imagery/bluemarble_world_2048.tif");
    const fs::path lux = pyramidOf(luxembourg, "luxembourg", "");
    const std::string before = manifestText(lux);
    // A 16-bit DEM given as imagery.
    expectRefused(run(TERRAIN_IMAGERY, lux.string() + " " + rainier.string()), lux, before,
                  "probably a DEM", rainier.string());
    // An image that misses the terrain.
    expectRefused(run(TERRAIN_IMAGERY, lux.string() + " " + boston.string()), lux, before,
                  "does not overlap", boston.string());
    // A truncated file.
    const fs::path cut = s_dir / "cut.tif";
    fs::copy_file(blueMarble, cut, fs::copy_options::overwrite_existing);
    fs::resize_file(cut, fs::file_size(cut) / 3);
    expectRefused(run(TERRAIN_IMAGERY, lux.string() + " " + cut.string()), lux, before, "truncated",
                  cut.string());
    // A CRS PROJ cannot place (an engineering site grid).
    GDALAllRegister();
    const fs::path local = s_dir / "site-grid.tif";
    {
        GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
            local.c_str(), 16, 16, 3, GDT_Byte, nullptr);
        ASSERT_NE(ds, nullptr);
        std::array<double, 6> gt = {0.0, 1.0, 0.0, 16.0, 0.0, -1.0};
        ds->SetGeoTransform(gt.data());
        OGRSpatialReference srs;
        srs.importFromWkt(R"(LOCAL_CS["a site grid",LOCAL_DATUM["site",32767],UNIT["metre",1],)"
                          R"(AXIS["Easting",EAST],AXIS["Northing",NORTH]])");
        ds->SetSpatialRef(&srs);
        GDALClose(ds);
    }
    expectRefused(run(TERRAIN_IMAGERY, lux.string() + " " + local.string()), lux, before,
                  "PROJ cannot transform", local.string());
    EXPECT_FALSE(fs::exists(lux / "imagery")) << "a refused build left a folder";
}

}  // namespace
}  // namespace terrain::io
