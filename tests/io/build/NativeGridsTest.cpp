// Native grids (terrain-build --globe --native-leaves; docs/globe.md, "Native leaves"): each
// longitude/latitude source's own samples, as the composite shows them, stored as a planar
// pyramid on its own grid grown by a patch's width. What must hold: at the finest level every
// sample the composite shows of the source is the source's own, bit for bit, whatever the cube
// faces do there (a source across a cube edge, a cap over a pole); a coarser source's grid
// under a finer one holds the finer surface; the margin holds the composite beyond the edge;
// and builds that cannot make them say so.
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/pyramid/PyramidReader.h"

#include "GeographicFunctionDem.h"
#include "GlobeTestSources.h"
#include "TempFolder.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace terrain::io {
namespace {

using test::GeographicFunctionDem;
using test::hills;
using test::TempFolder;

PyramidBuildOptions nativeLeaves() {
    PyramidBuildOptions options = test::smallGlobePatches();
    options.globeNativeLeaves = true;
    return options;
}

/// The finest level of a native grid's planar pyramid, sample by sample.
class NativeGrid {
public:
    explicit NativeGrid(const std::filesystem::path& folder) {
        auto opened = PyramidReader::open(folder);
        if (!opened) {
            ADD_FAILURE() << opened.error().message;
            return;
        }
        m_reader.emplace(std::move(opened.value()));
    }
    bool opened() const { return m_reader.has_value(); }
    const PyramidManifest& manifest() const { return m_reader->manifest(); }

    float at(std::int64_t column, std::int64_t row) {
        const PyramidLayout& layout = m_reader->layout();
        const int quads = layout.patchQuads();
        const int finest = layout.finestLevel();
        const PatchId id{finest, std::min(column / quads, layout.patchesX(finest) - 1),
                         std::min(row / quads, layout.patchesY(finest) - 1)};
        auto found = m_patches.find({id.x, id.y});
        if (found == m_patches.end()) {
            auto read = m_reader->readPatch(id);
            EXPECT_TRUE(read) << (read ? "" : read.error().message);
            found = m_patches
                        .emplace(std::pair(id.x, id.y),
                                 read ? read.value().heights : std::vector<float>{})
                        .first;
        }
        const int tile = layout.tileSamples();
        const auto i = column - id.x * quads, j = row - id.y * quads;
        return found->second[static_cast<std::size_t>((j + 1) * tile + i + 1)];
    }

private:
    std::optional<PyramidReader> m_reader;
    std::map<std::pair<std::int64_t, std::int64_t>, std::vector<float>> m_patches;
};

/// Every valid sample of `source` is its native grid's at (column + west, row + north).
void expectOwnSamples(NativeGrid& grid, DemReader& source, std::int64_t west, std::int64_t north,
                      std::int64_t skip = 0) {
    const DemInfo& info = source.info();
    std::vector<float> row(static_cast<std::size_t>(info.width));
    std::int64_t compared = 0;
    for (std::int64_t y = skip; y < info.height - skip; ++y) {
        ASSERT_TRUE(source.readWindow(0, y, info.width, 1, row));
        for (std::int64_t x = skip; x < info.width - skip; ++x) {
            const float own = row[static_cast<std::size_t>(x)];
            if (std::isnan(own)) continue;
            ASSERT_EQ(grid.at(x + west, y + north), own) << "sample (" << x << ", " << y << ")";
            ++compared;
        }
    }
    EXPECT_GT(compared, 0);
}

// A regional source across the cube edge between the +X and +Y faces (45° E): its grid is its
// own, not the faces', so every sample is stored as it is; the margin is a patch wide on every
// side, and beyond the source's one pixel of extension the bare ellipsoid (0 m).
TEST(NativeGrids, HoldTheSourcesOwnSamplesAcrossACubeEdge) {
    TempFolder temp;
    GeographicFunctionDem source(44.5, 11.0, 150, 100, 0.01, 0.01,
                                 [](double lat, double lon) { return hills(lat, lon) + 300.0f; });
    const auto out = temp.path() / "edge.pyramid";
    auto built = buildGlobePyramid(source, out, nativeLeaves());
    ASSERT_TRUE(built) << built.error().message;
    const PyramidManifest& m = built.value().manifest;
    ASSERT_EQ(m.globe->sources.size(), 1u);
    EXPECT_EQ(m.globe->sources[0].native, "native/0");
    auto reread = readManifest(out);
    ASSERT_TRUE(reread) << reread.error().message;
    EXPECT_EQ(reread.value().globe->sources, m.globe->sources);

    NativeGrid grid(out / "native/0");
    ASSERT_TRUE(grid.opened());
    const std::int64_t margin = test::smallGlobePatches().patchSamples - 1;
    const Georeference& g = grid.manifest().georeference;
    EXPECT_EQ(g.crsKind, CrsKind::Geographic);
    EXPECT_NEAR(g.originX, 44.5 - 0.01 * double(margin), 1e-9);
    EXPECT_NEAR(g.originY, 11.0 + 0.01 * double(margin), 1e-9);
    // Grown east and south to whole tiles: no tile is padded with made-up samples.
    const PyramidLayout& layout = grid.manifest().layout;
    EXPECT_GE(layout.rasterWidth(), 150 + 2 * margin);
    EXPECT_LT(layout.rasterWidth(), 150 + 3 * margin);
    EXPECT_EQ((layout.rasterWidth() - 1) % margin, 0);
    EXPECT_GE(layout.rasterHeight(), 100 + 2 * margin);
    EXPECT_EQ((layout.rasterHeight() - 1) % margin, 0);
    // Lossless: the finest level is the grid itself.
    EXPECT_EQ(grid.manifest().levels.back().maxError, 0.0);
    expectOwnSamples(grid, source, margin, margin);
    // Two pixels beyond the edge nothing is left of the source: the ellipsoid.
    EXPECT_EQ(grid.at(margin - 3, margin + 50), 0.0f);
    EXPECT_EQ(grid.at(margin + 150 + 2, margin + 50), 0.0f);
    EXPECT_EQ(grid.at(margin + 75, 0), 0.0f);
}

// A cap over the north pole, around every longitude: its grid stops at the pole (no row
// beyond it) and has no margin east or west (it wraps); every sample is its own.
TEST(NativeGrids, CapOverThePoleStopsAtThePole) {
    TempFolder temp;
    GeographicFunctionDem source(-180.0, 90.0, 360, 20, 1.0, 0.1,
                                 [](double lat, double lon) { return hills(lat, lon) + 200.0f; });
    const auto out = temp.path() / "pole.pyramid";
    auto built = buildGlobePyramid(source, out, nativeLeaves());
    ASSERT_TRUE(built) << built.error().message;
    NativeGrid grid(out / "native/0");
    ASSERT_TRUE(grid.opened());
    const std::int64_t margin = test::smallGlobePatches().patchSamples - 1;
    const Georeference& g = grid.manifest().georeference;
    EXPECT_NEAR(g.originX, -180.0, 1e-9);
    EXPECT_NEAR(g.originY, 90.0, 1e-9);
    // Round the Earth: no margin but the columns that make whole tiles (wrapped); north of it
    // the pole.
    EXPECT_EQ(grid.manifest().layout.rasterWidth(), 369);
    EXPECT_EQ(grid.manifest().layout.rasterHeight(), 20 + margin + 13);
    expectOwnSamples(grid, source, 0, 0);
}

// A fine regional source over a coarse global grid: the fine one's own samples are stored away
// from its edge (where it is blended into the coarse one, as the face grids take it); the
// coarse grid, where the fine source shows, holds the fine surface, not its own samples; and
// elsewhere its own samples.
TEST(NativeGrids, OverlappingSourcesEachHoldWhatTheCompositeShows) {
    TempFolder temp;
    GeographicFunctionDem coarse(-180.0, 90.0, 180, 90, 2.0, 2.0, hills);
    GeographicFunctionDem fine(20.0, 40.5, 400, 300, 0.01, 0.01,
                               [](double lat, double lon) { return hills(lat, lon) + 50.0f; });
    DemReader* const sources[] = {&coarse, &fine};
    const auto out = temp.path() / "composite.pyramid";
    auto built = buildGlobePyramid(sources, out, nativeLeaves());
    ASSERT_TRUE(built) << built.error().message;
    const PyramidManifest& m = built.value().manifest;
    ASSERT_EQ(m.globe->sources.size(), 2u);  // finest first
    EXPECT_EQ(m.globe->sources[0].native, "native/0");
    EXPECT_EQ(m.globe->sources[1].native, "native/1");

    NativeGrid fineGrid(out / "native/0");
    ASSERT_TRUE(fineGrid.opened());
    const std::int64_t margin = test::smallGlobePatches().patchSamples - 1;
    // The blend band at the fine source's edge is at least 24 pixels wide.
    ASSERT_EQ(m.globe->seams.size(), 1u);
    const auto band = static_cast<std::int64_t>(std::ceil(m.globe->seams[0].bandPixels[1]));
    ASSERT_LT(2 * band, 300);
    expectOwnSamples(fineGrid, fine, margin, margin, band);

    NativeGrid coarseGrid(out / "native/1");
    ASSERT_TRUE(coarseGrid.opened());
    // Around the Earth (no margin but whole tiles, wrapped), pole to pole.
    EXPECT_EQ(coarseGrid.manifest().layout.rasterWidth(), 193);
    EXPECT_EQ(coarseGrid.manifest().layout.rasterHeight(), 90);
    // The coarse sample at 21° E, 39° N (column 100, row 25) lies 100 pixels or more inside the
    // fine source, past its band: it holds the fine surface there (50 m above the hills, on
    // the fine triangles), not its own sample.
    ASSERT_LT(band, 100);
    const float fineThere = coarseGrid.at(100, 25);
    std::vector<float> own(1);
    ASSERT_TRUE(coarse.readWindow(100, 25, 1, 1, own));
    EXPECT_NEAR(fineThere, hills(39.0, 21.0) + 50.0f, 0.5);
    EXPECT_GT(std::abs(fineThere - own[0]), 40.0f);
    // Each finest tile's Err(P) covers the other source's samples shown on it: the coarse
    // tile under the fine source misses the fine hills' detail by metres, and the levels above
    // nest over it; a tile far from it misses nothing.
    auto coarseReader = PyramidReader::open(out / "native/1");
    ASSERT_TRUE(coarseReader);
    const int finest = coarseReader.value().layout().finestLevel();
    const int quads = coarseReader.value().layout().patchQuads();
    auto under = coarseReader.value().patchInfo({finest, 100 / quads, 25 / quads});
    auto far = coarseReader.value().patchInfo({finest, 0, 0});
    ASSERT_TRUE(under && far);
    EXPECT_GT(under.value().error, 1.0f);
    EXPECT_EQ(far.value().error, 0.0f);
    EXPECT_GE(coarseReader.value().manifest().statistics.rootError, under.value().error);
    // Far from the fine source, the coarse grid's own samples.
    for (const auto& [column, row] : {std::pair(10, 10), std::pair(150, 70), std::pair(90, 0)}) {
        ASSERT_TRUE(coarse.readWindow(column, row, 1, 1, own));
        EXPECT_EQ(coarseGrid.at(column, row), own[0]) << column << ", " << row;
    }
}

TEST(NativeGrids, BuildsThatCannotMakeThemSaySo) {
    TempFolder temp;
    GeographicFunctionDem source(44.5, 11.0, 150, 100, 0.01, 0.01, hills);
    DemReader* const sources[] = {&source};
    // (By shards they are built: GlobeShardsTest, NativeGridOf….)
    // Beyond the memory budget: refused by name, nothing left behind (the same build
    // without native leaves fits).
    PyramidBuildOptions tight = nativeLeaves();
    tight.memoryBudgetBytes = 300 << 10;
    auto over = buildPyramid(PyramidSurface::Globe, sources, temp.path() / "tight.pyramid", tight,
                             BuildWay::Whole);
    ASSERT_FALSE(over);
    EXPECT_NE(over.error().message.find("its native grid (--native-leaves) needs about"),
              std::string::npos)
        << over.error().message;
    EXPECT_FALSE(std::filesystem::exists(temp.path() / "tight.pyramid"));
    tight.globeNativeLeaves = false;
    EXPECT_TRUE(buildPyramid(PyramidSurface::Globe, sources, temp.path() / "tight.pyramid", tight,
                             BuildWay::Whole));
    // A planar pyramid's finest level is the source's grid already.
    auto planar =
        buildPyramid(PyramidSurface::Plane, sources, temp.path() / "plane.pyramid", nativeLeaves());
    ASSERT_FALSE(planar);
    EXPECT_NE(planar.error().message.find("planar"), std::string::npos) << planar.error().message;
}

// A manifest naming a native grid anywhere but a numbered folder inside the pyramid is refused,
// naming the field: nothing in a manifest may lead a reader out of the pyramid.
TEST(NativeGrids, AManifestCannotPointOutsideThePyramid) {
    TempFolder temp;
    GeographicFunctionDem source(44.5, 11.0, 150, 100, 0.01, 0.01, hills);
    const auto out = temp.path() / "p.pyramid";
    auto built = buildGlobePyramid(source, out, nativeLeaves());
    ASSERT_TRUE(built) << built.error().message;
    nlohmann::json manifest;
    {
        std::ifstream in(out / "manifest.json");
        in >> manifest;
    }
    for (const char* bad : {"../native/0", "native/", "native/0/../../x", "/tmp/native/0", "x/1"}) {
        manifest["globe"]["sources"][0]["native"] = bad;
        std::ofstream(out / "manifest.json") << manifest.dump(2);
        auto read = readManifest(out);
        ASSERT_FALSE(read) << bad;
        EXPECT_NE(read.error().message.find("native grid"), std::string::npos)
            << read.error().message;
    }
}

}  // namespace
}  // namespace terrain::io
