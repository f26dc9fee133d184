// terrain-planet-imagery: how fast the virtual planet's colours (PlanetImagery, issue 47) are
// generated on one core, the I/O thread's cost a tile, and a picture of them: the six faces
// unfolded as a cross, the interior texels of every tile of a face level side by side.
#include "CommandLine.h"
#include "NumberChecks.h"

#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/ImageryTileSource.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"

#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using namespace terrain;

int fail(const std::string& message) {
    fmt::print(stderr, "terrain-planet-imagery: {}\n", message);
    return 1;
}

// The picture's tiles: every tile of a face level on each face, or a square of them around
// one point.
struct PictureTiles {
    int face = 0;
    std::int64_t x0 = 0, y0 = 0;  ///< the first tile, in the face's tiles
    int across = 1;               ///< tiles a side
};

// Where each face sits in the unfolded cross, in faces (column, row): the four around the
// equator in a row (0 +X, 1 +Y, 2 −X, 3 −Y), the north pole above +X, the south below it.
// Each face is drawn as its (s, t) raster; the poles' edges meet the row only along +X.
constexpr std::array<std::array<int, 2>, globe::kCubeFaces> kCrossCell{
    {{0, 1}, {1, 1}, {2, 1}, {3, 1}, {0, 0}, {0, 2}}};

// The picture as a binary PPM (P6), written to a temporary name and renamed: nothing half
// written.
Status writePicture(io::ImageryTileSource& source, int faceLevel,
                    const std::optional<PictureTiles>& around, const std::string& file) {
    const int tiles = around ? around->across : 1 << faceLevel;
    const int faceTexels = tiles * io::kImageryInteriorTexels;
    const int width = around ? faceTexels : 4 * faceTexels;
    const int height = around ? faceTexels : 3 * faceTexels;
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3, 0);
    io::ImageryTile tile;
    const std::int64_t perFace = std::int64_t{1} << faceLevel;
    for (int face = 0; face < globe::kCubeFaces; ++face) {
        if (around && face != around->face) continue;
        const std::array<int, 2> cell = around ? std::array<int, 2>{0, 0} : kCrossCell[face];
        for (int y = 0; y < tiles; ++y) {
            for (int x = 0; x < tiles; ++x) {
                const std::int64_t tx = around ? around->x0 + x : x;
                const std::int64_t ty = around ? around->y0 + y : y;
                const io::PatchId id{io::ManifestGlobe::kLevelOffset + faceLevel,
                                     std::int64_t{face} * perFace + tx, ty};
                if (Status read = source.readTile(id, tile); !read) return read;
                for (int j = 0; j < io::kImageryInteriorTexels; ++j) {
                    for (int i = 0; i < io::kImageryInteriorTexels; ++i) {
                        const std::size_t from =
                            4 * (static_cast<std::size_t>(j + io::kImageryBorderTexels) *
                                     io::kImageryTileTexels +
                                 static_cast<std::size_t>(i + io::kImageryBorderTexels));
                        const std::size_t px = static_cast<std::size_t>(
                            cell[0] * faceTexels + x * io::kImageryInteriorTexels + i);
                        const std::size_t py = static_cast<std::size_t>(
                            cell[1] * faceTexels + y * io::kImageryInteriorTexels + j);
                        for (std::size_t c = 0; c < 3; ++c)
                            rgb[3 * (py * static_cast<std::size_t>(width) + px) + c] =
                                tile.rgba[from + c];
                    }
                }
            }
        }
    }
    const std::string partial = file + ".partial";
    {
        std::ofstream out(partial, std::ios::binary);
        out << "P6\n" << width << ' ' << height << "\n255\n";
        out.write(reinterpret_cast<const char*>(rgb.data()),
                  static_cast<std::streamsize>(rgb.size()));
        if (!out) return Error{fmt::format("{}: cannot write the picture", file)};
    }
    std::error_code error;
    std::filesystem::rename(partial, file, error);
    if (error) return Error{fmt::format("{}: cannot write the picture: {}", file, error.message())};
    return {};
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"The virtual planet's imagery: tiles per second on one core, or a picture"};
    std::string planetName = "planet:";
    int faceLevel = 8;
    double seconds = 3.0;
    std::string picture;
    int pictureLevel = 1;
    bool json = false;
    app.add_option("planet", planetName, "the virtual planet (planet:seed=…,level=…)");
    app.add_option("--face-level", faceLevel,
                   "face level of the tiles timed (random tiles of it), 0 … the layer's finest")
        ->check(CLI::Range(0, io::kMaxGlobeFaceLevel));
    app.add_option("--seconds", seconds, "time at least this long")->check(tools::positiveNumber());
    app.add_option("--picture", picture, "write the six faces unfolded as a cross (binary PPM)");
    app.add_option("--picture-level", pictureLevel, "face level of the picture's tiles")
        ->check(CLI::Range(0, io::kMaxGlobeFaceLevel));
    std::vector<double> at;
    app.add_option("--at", at,
                   "LAT LON: picture the 4 × 4 tiles around this point (degrees) instead of the "
                   "whole faces (above --picture-level 4: around the highest summit)")
        ->expected(2);
    app.add_flag("--json", json, "print the figures as JSON");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    auto planet = io::VirtualPlanetPyramid::open(planetName);
    if (!planet) return fail(planet.error().message);
    const io::PyramidManifest& manifest = planet.value().manifest();
    if (manifest.imagery.empty()) return fail(planetName + ": has no imagery layer (imagery=0)");
    const io::ManifestImageryLayer& layer = manifest.imagery.front();
    auto source = io::openImageryTiles(planetName, manifest, layer);
    if (!source) return fail(source.error().message);

    if (!picture.empty()) {
        std::optional<PictureTiles> around;
        if (at.empty() && pictureLevel > 4) {
            // Around the highest summit the planet's search found (its manifest's extent).
            at = {0.5 * (manifest.globe->south + manifest.globe->north),
                  0.5 * (manifest.globe->west + manifest.globe->east)};
        }
        if (!at.empty()) {
            const double lat = at[0] * std::numbers::pi / 180.0,
                         lon = at[1] * std::numbers::pi / 180.0;
            const globe::FacePoint p = globe::facePointOf(
                {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)});
            const std::int64_t perFace = std::int64_t{1} << pictureLevel;
            const int across = static_cast<int>(std::min<std::int64_t>(4, perFace));
            const auto first = [&](double c) {
                return std::clamp<std::int64_t>(
                    static_cast<std::int64_t>(std::floor(c * static_cast<double>(perFace))) -
                        across / 2,
                    0, perFace - across);
            };
            around = PictureTiles{p.face, first(p.s), first(p.t), across};
        }
        if (Status written = writePicture(*source.value(), pictureLevel, around, picture); !written)
            return fail(written.error().message);
    }

    const int level = io::ManifestGlobe::kLevelOffset + faceLevel;
    if (level > layer.finestLevel)
        return fail(fmt::format("--face-level {}: the layer's finest face level is {}", faceLevel,
                                layer.finestLevel - io::ManifestGlobe::kLevelOffset));
    // Random tiles of the level: the first of a level pays for its low-passed planet once.
    std::mt19937_64 rng(1);
    const std::int64_t perFace = std::int64_t{1} << faceLevel;
    std::uniform_int_distribution<std::int64_t> column(0, globe::kCubeFaces * perFace - 1),
        row(0, perFace - 1);
    io::ImageryTile tile;
    if (Status warm = source.value()->readTile({level, 0, 0}, tile); !warm)
        return fail(warm.error().message);
    std::int64_t count = 0;
    const Clock::time_point start = Clock::now();
    double elapsed = 0.0;
    while (elapsed < seconds) {
        if (Status read = source.value()->readTile({level, column(rng), row(rng)}, tile); !read)
            return fail(read.error().message);
        ++count;
        elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    }
    const double tilesPerSecond = static_cast<double>(count) / elapsed;
    if (json) {
        const nlohmann::json j{{"planet", planetName},
                               {"layer", layer.name},
                               {"face_level", faceLevel},
                               {"tiles", count},
                               {"seconds", elapsed},
                               {"tiles_per_s", tilesPerSecond},
                               {"ms_per_tile", 1000.0 * elapsed / static_cast<double>(count)}};
        fmt::print("{}\n", j.dump(2));
    } else {
        fmt::print(
            "{} \"{}\", face level {}: {} tiles in {:.2f} s, {:.1f} tiles/s ({:.1f} ms a "
            "tile) on one core\n",
            planetName, layer.name, faceLevel, count, elapsed, tilesPerSecond,
            1000.0 * elapsed / static_cast<double>(count));
    }
    return 0;
}
