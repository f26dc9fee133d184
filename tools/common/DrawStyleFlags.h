// The command-line flags of the terrain draw's look, shared by the programs that show it
// (terrain-render, terrain-view).
#pragma once

#include "NumberChecks.h"

#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace terrain::tools {

struct DrawStyleFlags {
    std::string debugView = "shaded";
    bool wireframe = false;
    bool noSkirts = false;
    double fogDensity = -1.0;  ///< < 0: from the DEM's extent
    bool noImagery = false;
    bool imageryUnlit = false;
    std::vector<float> imageryOpacity;  ///< per layer, bottom first; missing ones 1

    /// Adds --debug-view, --wireframe, --no-skirts, the imagery's flags and --fog; returns
    /// --fog.
    CLI::Option* addTo(CLI::App& app) {
        app.add_option("--debug-view", debugView,
                       "shaded, level (colour by patch level), tess (by tessellation factor) or "
                       "patch (each patch's draw index in the colour's bytes, unlit)")
            ->capture_default_str()
            ->check(CLI::IsMember({"shaded", "level", "tess", "patch"}));
        app.add_flag("--wireframe", wireframe, "Draw triangle edges");
        app.add_flag("--no-skirts", noSkirts,
                     "Leave out the skirts (shows cracks between patches)");
        app.add_flag("--no-imagery", noImagery,
                     "Draw the tint alone, without the pyramid's imagery layers");
        app.add_flag("--imagery-unlit", imageryUnlit,
                     "Draw imagery as it is (its shadows baked in), not lit by the sun");
        app.add_option("--imagery-opacity", imageryOpacity,
                       "Each imagery layer's opacity, bottom first, times the manifest's "
                       "(0 hides a layer; layers not given keep 1)")
            ->delimiter(',')
            ->check(CLI::Range(0.0, 1.0));
        return app
            .add_option("--fog", fogDensity,
                        "Fog density per metre (default from the DEM's extent)")
            ->check(nonNegativeNumber());
    }

    runtime::TerrainDebugView debugViewValue() const {
        if (debugView == "level") return runtime::TerrainDebugView::Level;
        if (debugView == "tess") return runtime::TerrainDebugView::TessFactor;
        if (debugView == "patch") return runtime::TerrainDebugView::PatchId;
        return runtime::TerrainDebugView::Shaded;
    }

    /// Sets the style's imagery from the flags.
    void applyImagery(runtime::TerrainStyle& style) const {
        style.imagery = !noImagery;
        style.imageryLighting = !imageryUnlit;
        for (std::size_t i = 0; i < style.imageryOpacity.size(); ++i)
            style.imageryOpacity[i] = i < imageryOpacity.size() ? imageryOpacity[i] : 1.0f;
    }

    /// --fog, or by default 1 − e^−0.5 ≈ 39 % fog across the DEM's larger side.
    float fogDensityPerM(const runtime::TerrainGeometry& geometry) const {
        const glm::dvec2 extent = geometry.demSize();
        return static_cast<float>(
            fogDensity >= 0.0 ? fogDensity : 0.5 / std::max(1.0, std::max(extent.x, extent.y)));
    }
};

}  // namespace terrain::tools
