// GlobeReferenceScene: the globe's reference (ReferenceScene.h; docs/globe.md): a globe
// pyramid's finest data everywhere in view, every sample a vertex, placed on the ellipsoid as
// the globe draw places it (surface_globe.glsl, with the frames globePatchInstance writes).
//
// It walks the pyramid on disk from the six face roots: into every present child, and where a
// child is absent it draws that quadrant from its parent's tile (bilinear between the tile's
// samples, as the LOD's virtual patches); a patch with no children is drawn sample for
// sample. Each such region is a grid of patchQuads² cells, each cell split along its
// north-west–south-east diagonal, and is split into four only where the ellipsoid's bulge
// over its flat cells would show on screen (more than kCurvatureTolerancePx): coarse data
// seen from close by is still drawn on the curved surface. Where data of different levels
// meet (a source's edge) the coarser side's edge is interpolated: without skirts a sliver of
// background can show there, in the reference alone.
#pragma once

#include "terrain/globe/GlobePatch.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/ReferenceScene.h"

#include <array>
#include <cstdint>
#include <map>

namespace terrain::runtime {

class GlobeReferenceScene final : public ReferenceScene {
public:
    /// A region is split until its flat cells fall under the ellipsoid by at most this on
    /// screen: a twentieth of the measures' 0.05 px tolerance would be below float depth.
    static constexpr double kCurvatureTolerancePx = 0.05;
    /// The finest level a region is split to for curvature (a patch there is ~15 cm wide).
    static constexpr int kMaxRegionLevel = 24;

    /// The scene of the globe pyramid `pyramid` (manifest.globe set), read through it (it
    /// must outlive the scene).
    explicit GlobeReferenceScene(io::PyramidReader& pyramid);

    std::string name() const override { return "globe reference"; }
    std::string vertexStage() const override { return "globe_reference.vert"; }
    bool globe() const override { return true; }
    int gridQuads() const override { return m_layout.patchQuads(); }
    int tileSamples() const override { return m_layout.tileSamples(); }
    void beginFrame(const Camera& camera, FrameBlock& block) override;
    /// A face no source covers is drawn as the bare ellipsoid. Past `maxRegions` patches and
    /// regions walked it stops.
    Result<bool> addInstances(const Camera& camera, ReferenceBatch& batch,
                              std::uint64_t maxRegions) override;

private:
    // A patch-sized grid drawn from the tile of `tileId`: patch sample s lies on tile
    // sample texelOffset + s · texelStep.
    struct Region {
        globe::GlobePatchId id;
        globe::GlobePatchId tileId;
        double texelOffsetX = 0.0, texelOffsetY = 0.0, texelStep = 1.0;
        float minHeight = 0.0f, maxHeight = 0.0f;
        bool bare = false;  // a face no source covers: the ellipsoid, no tile
    };

    Status visitPatch(const globe::GlobePatchId& id, const io::PatchInfo& info);
    Status visitRegion(const Region& region);
    bool withinLimit();  // counts one more patch or region; false past m_maxRegions
    Status addRegion(const Region& region);
    Result<const io::PatchRecord*> tileOf(const globe::GlobePatchId& id);

    io::PyramidReader& m_pyramid;
    io::PyramidLayout m_layout;

    // Per draw.
    ReferenceBatch* m_batch = nullptr;
    const Camera* m_camera = nullptr;
    Frustum m_frustum;
    std::uint64_t m_maxRegions = 0;
    std::uint64_t m_visited = 0;  // patches and regions walked this draw
    bool m_complete = true;
    double m_gamma = 1.0;
    glm::dvec3 m_cameraUp{0.0};
    std::map<std::uint64_t, io::PatchRecord> m_tiles;  // read this draw, by layout patch
};

}  // namespace terrain::runtime
