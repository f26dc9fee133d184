// RtinStrategy: the RTIN yardstick as a LodStrategy (LodMethod::Rtin). It reads the
// pyramid's finest level once into memory (RtinMesh says how much it may hold), refines the
// mesh on the CPU for each frame's camera, and draws it as one indexed triangle list placed
// and shaded as the reference renderer's. It streams nothing: it measures how few
// triangles a conforming mesh of the full-resolution samples needs, not a runtime.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/LodStrategy.h"
#include "terrain/runtime/PlaneFrame.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/RtinMesh.h"

#include <array>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

namespace terrain::runtime {

class RtinStrategy final : public LodStrategy {
public:
    /// Reads the pyramid (planar only; errors name it) and builds the mesh's errors.
    static Result<std::unique_ptr<RtinStrategy>> open(
        const std::filesystem::path& pyramid, double errorPx,
        std::size_t maxBytes = RtinMesh::kDefaultMaxBytes);

    LodMethod method() const override { return LodMethod::Rtin; }
    const Surface& surface() const override { return *m_surface; }
    void setErrorPx(double errorPx) override { m_errorPx = errorPx; }
    double errorPx() const override { return m_errorPx; }

    const LodUpdateStats& beginFrame(const Camera& camera) override;
    /// Shaded only (style.debugView is ignored); no skirts, nothing to cull on the GPU.
    TerrainDrawStats draw(const Camera& camera, const TerrainStyle& style) override;
    void endFrame(FrameTelemetry& t) override;
    double lodUpdateUs() const override { return m_lodUpdateUs; }

    bool settle(const Camera&, std::chrono::milliseconds) override { return true; }
    std::uint64_t loadsOutstanding() const override { return 0; }
    const TileFault* fatalFault() const override { return nullptr; }
    void drain(std::chrono::milliseconds) override {}
    /// The mesh's CPU arrays and the GPU buffers.
    std::uint64_t memoryBytes() const override;

    const RtinMesh& mesh() const { return m_mesh; }
    const std::vector<RtinTriangle>& triangles() const { return m_triangles; }

private:
    RtinStrategy(const io::PyramidManifest& manifest, RtinMesh mesh, gl::Program program,
                 gl::Query timeQuery, double errorPx);
    /// Writes this frame's vertices (relative to `anchor`) and indices into the buffers.
    void upload(glm::dvec2 anchor);

    struct Vertex {
        std::array<float, 3> sampleHeight;
        std::array<float, 3> normal;
    };

    std::unique_ptr<PlaneSurface> m_surface;
    RtinMesh m_mesh;
    gl::Program m_program;
    PlaneFrame m_frame;  // the camera, the anchor frame and the look of the draw
    gl::Query m_timeQuery;
    gl::VertexArray m_vertexArray;
    gl::Buffer m_vertexBuffer;
    gl::Buffer m_indexBuffer;
    double m_errorPx = 1.0;

    std::vector<RtinTriangle> m_triangles;
    std::vector<Vertex> m_vertices;
    std::vector<std::uint32_t> m_indices;
    std::vector<std::uint32_t> m_gridVertices;  // this frame's grid vertices, sorted, unique
    bool m_uploaded = false;  // the buffers hold this frame's mesh relative to m_uploadedAnchor
    glm::dvec2 m_uploadedAnchor{0.0};

    LodUpdateStats m_stats;
    double m_lodUpdateUs = 0.0;
    TerrainDrawStats m_lastDraw;
};

}  // namespace terrain::runtime
