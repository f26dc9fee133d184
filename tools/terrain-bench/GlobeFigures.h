// GlobeFigures: what terrain-bench reports of a globe pyramid beside its flight (docs/globe.md,
// "Figures"): the patches the same view needs at a pole, on the equator and over the cube's
// edge and corner, and the samples the pyramid stores against a longitude/latitude grid of the
// same equatorial spacing. No GL draw.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/TerrainSession.h"

#include <nlohmann/json.hpp>

#include <string>

namespace terrain::tools {

/// {"same_view_straight_down_10km": [...], "storage": {...}} of the globe pyramid `pyramid`
/// (manifest.globe set), its LOD opened with `options`, the view `widthPx` × `heightPx`.
Result<nlohmann::json> globeFigures(const std::string& pyramid, const io::PyramidManifest& manifest,
                                    const runtime::TerrainSessionOptions& options, int widthPx,
                                    int heightPx);

}  // namespace terrain::tools
