// TinyPyramids: a planar and a globe pyramid of the built-in procedural terrain, built once
// per process into the scratch folder with the project's own builders: what the shard and
// manifest targets mutate (their seeds are these pyramids' own files).
#pragma once

#include "FuzzScratch.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/source/DemReader.h"
#include "terrain/source/ProceduralDems.h"

#include <filesystem>

namespace terrain::fuzz {

inline io::PyramidBuildOptions tinyBuildOptions() {
    io::PyramidBuildOptions options;
    options.patchSamples = 33;
    options.blockQuads = 8;
    options.shardPatches = 2;
    options.threads = 1;
    return options;
}

/// 65 × 65 samples 10 m apart: two levels, the finest in one shard of 2 × 2 patches.
inline const fs::path& tinyPlanarPyramid() {
    static const fs::path pyramid = [] {
        const fs::path out = scratch() / "planar.pyramid";
        auto dem = io::openProceduralDem("procedural:size=65,seed=7,spacing=10");
        if (!dem) harnessFailure(dem.error().message);
        auto built = io::buildPyramid(*dem.value(), out, tinyBuildOptions());
        if (!built) harnessFailure(built.error().message);
        return out;
    }();
    return pyramid;
}

/// The same terrain as a 16° × 16° longitude/latitude grid on the globe (sparse: only the
/// patches under it exist).
inline const fs::path& tinyGlobePyramid() {
    static const fs::path pyramid = [] {
        const fs::path out = scratch() / "globe.pyramid";
        // As terrain-build --epsg 4326 --spacing 0.25 --origin 10,50 places it.
        auto dem = io::openProceduralDem(
            "procedural:size=65,seed=7,spacing=10", [](io::DemInfo& info) -> Status {
                info.georeference = {.originX = 10.0,
                                     .originY = 50.0,
                                     .pixelSizeX = 0.25,
                                     .pixelSizeY = 0.25,
                                     .epsg = io::Georeference::kWgs84Geographic,
                                     .crsKind = io::CrsKind::Geographic};
                return {};
            });
        if (!dem) harnessFailure(dem.error().message);
        auto built = io::buildGlobePyramid(*dem.value(), out, tinyBuildOptions());
        if (!built) harnessFailure(built.error().message);
        return out;
    }();
    return pyramid;
}

}  // namespace terrain::fuzz
