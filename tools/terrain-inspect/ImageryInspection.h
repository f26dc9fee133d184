// The imagery layers of a pyramid as terrain-inspect shows them (docs/imagery.md): per layer
// its levels, tiles and bytes from layer.json, and with --verify every tile file read back
// and each tile checked (table, CRC-32, WebP decode).
#pragma once

#include "PatchChecks.h"

#include "terrain/pyramid/PyramidManifest.h"

#include <filesystem>
#include <string>
#include <vector>

namespace terrain::inspect {

struct ImageryLayerSummary {
    std::string name;
    std::string kind;
    int coarsestLevel = 0, finestLevel = 0;
    double opacity = 1.0;
    std::int64_t tiles = 0;      ///< present tiles (stored layers)
    std::int64_t bytes = 0;      ///< of the tile files
    std::int64_t verified = -1;  ///< tiles checked by --verify; -1 when not verified
};

/// One summary per layer; problems (an unreadable index, a damaged file) are appended.
std::vector<ImageryLayerSummary> inspectImagery(const std::filesystem::path& pyramidDir,
                                                const io::PyramidManifest& manifest, bool verify,
                                                std::vector<Problem>& problems);

}  // namespace terrain::inspect
