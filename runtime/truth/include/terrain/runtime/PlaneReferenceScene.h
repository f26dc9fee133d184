// PlaneReferenceScene: the plane's reference (ReferenceScene.h): the full-resolution DEM,
// every sample of the pyramid's finest level a vertex. It draws the DEM's extent only (the
// finest level's last patches overhang it with clamped copies of its edge, which
// reference.frag discards). The finest level is cut into tiles of at most kMaxTileQuads quads
// a side; the tiles whose footprint and height range meet the view frustum are drawn, each
// cell split along its north-west–south-east diagonal (FullResolutionSurface::heightAt's
// referenceM), placed relative to the camera's anchor sample as the LOD draw places patches.
#pragma once

#include "terrain/runtime/FullResolutionSurface.h"
#include "terrain/runtime/ReferenceScene.h"

#include <memory>
#include <span>
#include <vector>

namespace terrain::runtime {

class PlaneReferenceScene final : public ReferenceScene {
public:
    static constexpr int kMaxTileQuads = 128;

    /// The scene of `surface`'s finest level, which it reads its tiles through (it must
    /// outlive the scene).
    explicit PlaneReferenceScene(FullResolutionSurface& surface);

    std::string name() const override { return "reference"; }
    std::string vertexStage() const override { return "reference.vert"; }
    bool globe() const override { return false; }
    int gridQuads() const override { return m_tileQuads; }
    int tileSamples() const override { return m_tileQuads + 3; }  // with a one-sample apron
    void beginFrame(const Camera& camera, FrameBlock& block) override;
    Result<bool> addInstances(const Camera& camera, ReferenceBatch& batch,
                              std::uint64_t maxRegions) override;

private:
    /// Window (windowX, windowY) of kMaxTileQuads quads a side of patch `id`'s tile, with a
    /// one-sample apron, in the scratch (valid until the next call).
    Result<std::span<const float>> cutWindow(const io::PatchId& id, int windowX, int windowY);

    FullResolutionSurface& m_surface;
    int m_tileQuads = 0;
    glm::dvec2 m_anchor{0.0};  // DEM samples, this frame's
    std::vector<float> m_tileScratch;
};

}  // namespace terrain::runtime
