#include "GlobeFigures.h"

#include "terrain/runtime/GlobeCamera.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <tuple>

namespace terrain::tools {

Result<nlohmann::json> globeFigures(const std::string& pyramid, const io::PyramidManifest& manifest,
                                    const runtime::TerrainSessionOptions& options, int widthPx,
                                    int heightPx) {
    // The same view straight down from 10 km at a pole, on the equator, over a cube edge and
    // over a cube corner (where the data reaches: a regional pyramid draws bare ellipsoid
    // elsewhere).
    nlohmann::json sameView = nlohmann::json::array();
    auto opened = runtime::TerrainSession::open(pyramid, options);
    if (!opened) return opened.error();
    runtime::TerrainSession& session = *opened.value();
    runtime::Camera camera;
    camera.viewportWidth = widthPx;
    camera.viewportHeight = heightPx;
    camera.fovY = 50.0 * std::numbers::pi / 180.0;
    for (const auto& [name, lat, lon] :
         {std::tuple{"north pole", 90.0, 0.0}, std::tuple{"south pole", -90.0, 0.0},
          std::tuple{"equator", 0.0, 0.0}, std::tuple{"cube edge", 0.0, 45.0},
          std::tuple{"cube corner", 35.26439, 45.0}}) {
        runtime::placeOnGlobe(camera, {{lat, lon, 10e3}, 0.0, -90.0});
        // Each place's own cut, as a fresh LOD chooses it: not what the tree kept of the
        // place before (a teleport merges what it no longer needs a level a frame).
        session.restartLod();
        session.settle(camera, std::chrono::seconds(60));
        const runtime::LodUpdateStats lod = session.beginFrame(camera);
        runtime::FrameTelemetry ignored;
        session.endFrame(ignored);
        sameView.push_back({{"place", name},
                            {"patches", lod.drawn},
                            {"data_patches", lod.drawn - lod.drawnBare - lod.drawnVirtual}});
    }

    // Samples stored against a longitude/latitude grid of the same equatorial spacing: the
    // finest face grid's spacing along the equator at a face centre is π/2 / (2^L·(N−1))
    // radians, where a lon/lat grid needs 2π/that × π/that samples (8 faces' worth, not 6).
    std::uint64_t storedSamples = 0;
    const auto tile = static_cast<std::uint64_t>(manifest.layout.patchSamples());
    for (const io::ManifestLevel& level : manifest.levels)
        storedSamples += static_cast<std::uint64_t>(level.presentPatches) * tile * tile;
    const double faceSamples =
        std::ldexp(double(manifest.layout.patchQuads()), manifest.globe->faceFinestLevel);
    const nlohmann::json storage{
        {"stored_samples_all_levels", storedSamples},
        {"finest_level_samples_whole_globe", 6.0 * faceSamples * faceSamples},
        {"lon_lat_grid_same_equatorial_spacing", 8.0 * faceSamples * faceSamples},
        {"whole_globe_ratio", 6.0 / 8.0}};
    return nlohmann::json{{"same_view_straight_down_10km", sameView}, {"storage", storage}};
}

}  // namespace terrain::tools
