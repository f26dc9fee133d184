// ViewerSettings: what the user can change while flying, edited by keys and by the overlay
// in place; the viewer applies whatever differs from what it applied last.
#pragma once

#include "terrain/runtime/TerrainRenderer.h"

#include <array>

namespace terrain::view {

struct ViewerSettings {
    double errorPx = 2.0;  ///< ε of the LOD tree and of the tessellation, pixels
    runtime::TerrainDebugView debugView = runtime::TerrainDebugView::Shaded;
    bool wireframe = false;
    bool skirts = true;
    bool fog = true;
    float fogDensityPerM = 0.0f;
    bool lodFrozen = false;
    bool vsync = true;
    bool keepAboveGround = true;
    int measureEvery = 30;  ///< frames between measured draws (triangles, GPU time); 1: all
    bool overlayVisible = true;
    // Imagery (issue 47): drawn or not, lit or as it is, and per manifest layer whether it is
    // shown and its opacity (times the manifest's), composited in `imageryOrder` (bottom
    // first, manifest indices).
    bool imagery = true;
    bool imageryLit = true;
    std::array<bool, 4> imageryShown{true, true, true, true};
    std::array<float, 4> imageryOpacity{1.0f, 1.0f, 1.0f, 1.0f};
    std::array<int, 4> imageryOrder{0, 1, 2, 3};

    // Cache budgets as edited in the overlay; they take effect when the user applies them,
    // which re-opens the pyramid (TileStreamer's budgets are fixed when it opens).
    double cpuCacheMiB = 256.0;
    int gpuLayers = 1024;

    // The jump-to-coordinates fields: on the plane world x, y and the height above the
    // ground; on a globe latitude, longitude and the altitude above WGS84.
    double jumpX = 0.0;
    double jumpY = 0.0;
    double jumpHeightM = 500.0;

    static constexpr double kMinErrorPx = 0.1;
    static constexpr double kMaxErrorPx = 64.0;
};

}  // namespace terrain::view
