// RtinStrategy: the finest level read into memory, the CPU refinement per frame and one
// indexed draw.
#include "terrain/runtime/RtinStrategy.h"

#include "terrain/gl/ReversedZScope.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/FinestLevelRaster.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <epoxy/gl.h>
#include <fmt/core.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>

namespace terrain::runtime {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

Result<std::unique_ptr<RtinStrategy>> RtinStrategy::open(const std::filesystem::path& pyramid,
                                                         double errorPx, std::size_t maxBytes) {
    auto reader = openPlanarPyramid(pyramid, "the RTIN yardstick");
    if (!reader) return reader.error();
    const io::PyramidManifest& manifest = reader.value().manifest();
    const TerrainGeometry geometry(manifest);
    const io::PyramidLayout& layout = geometry.layout();
    // Refused before a sample is read when the mesh would not fit.
    const auto width = static_cast<int>(layout.rasterWidth());
    const auto height = static_cast<int>(layout.rasterHeight());
    if (auto fits = RtinMesh::checkMemory(width, height, maxBytes); !fits)
        return Error{pyramid.string() + ": " + fits.error().message};
    auto raster = readFinestLevel(reader.value());
    if (!raster) return Error{pyramid.string() + ": " + raster.error().message};
    auto mesh = RtinMesh::build(width, height, std::move(raster).value(), geometry.sampleSpacing(),
                                maxBytes);
    if (!mesh) return Error{pyramid.string() + ": " + mesh.error().message};

    ProgramBuilder builder("rtin");
    builder.stage("rtin.vert").stage("reference.frag");
    auto program = builder.build();
    if (!program) return program.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "rtin GPU time");
    if (!time) return time.error();
    return std::unique_ptr<RtinStrategy>(new RtinStrategy(manifest, std::move(mesh).value(),
                                                          std::move(program).value(),
                                                          std::move(time).value(), errorPx));
}

RtinStrategy::RtinStrategy(const io::PyramidManifest& manifest, RtinMesh mesh, gl::Program program,
                           gl::Query timeQuery, double errorPx)
    : m_surface(std::make_unique<PlaneSurface>(manifest)),
      m_mesh(std::move(mesh)),
      m_program(std::move(program)),
      m_frame(m_surface->geometry(), "rtin frame"),
      m_timeQuery(std::move(timeQuery)),
      m_vertexArray(gl::VertexArray::create("rtin mesh")),
      m_errorPx(errorPx) {}

const LodUpdateStats& RtinStrategy::beginFrame(const Camera& camera) {
    const auto start = Clock::now();
    const RtinSelectStats selected =
        m_mesh.select(camera, m_surface->geometry().origin(), m_errorPx, true, m_triangles);
    m_lodUpdateUs = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    m_stats = {};
    m_stats.evaluations = selected.visited;
    m_stats.nodes = selected.visited;  // the bintree nodes this frame's refinement looked at
    m_stats.culled = selected.culled;
    m_uploaded = false;
    m_lastDraw = {};
    return m_stats;
}

void RtinStrategy::upload(glm::dvec2 anchor) {
    m_gridVertices.clear();
    for (const RtinTriangle& t : m_triangles)
        m_gridVertices.insert(m_gridVertices.end(), {t.a, t.b, t.c});
    std::sort(m_gridVertices.begin(), m_gridVertices.end());
    m_gridVertices.erase(std::unique(m_gridVertices.begin(), m_gridVertices.end()),
                         m_gridVertices.end());
    m_vertices.clear();
    const glm::dvec2 spacing = m_surface->geometry().sampleSpacing();
    for (const std::uint32_t v : m_gridVertices) {
        const glm::ivec2 s = m_mesh.sampleOf(v);
        const float h = m_mesh.heightAt(s.x, s.y);
        // Central differences over the full-resolution samples, as reference.vert takes
        // them. Rows run south.
        const double dx = m_mesh.heightAt(s.x + 1, s.y) - m_mesh.heightAt(s.x - 1, s.y);
        const double dy = m_mesh.heightAt(s.x, s.y - 1) - m_mesh.heightAt(s.x, s.y + 1);
        const glm::dvec3 normal =
            glm::normalize(glm::dvec3(-dx / (2.0 * spacing.x), -dy / (2.0 * spacing.y), 1.0));
        m_vertices.push_back(
            {{static_cast<float>(s.x - anchor.x), static_cast<float>(s.y - anchor.y), h},
             {static_cast<float>(normal.x), static_cast<float>(normal.y),
              static_cast<float>(normal.z)}});
    }
    m_indices.clear();
    const auto slot = [&](std::uint32_t v) {
        return static_cast<std::uint32_t>(
            std::lower_bound(m_gridVertices.begin(), m_gridVertices.end(), v) -
            m_gridVertices.begin());
    };
    for (const RtinTriangle& t : m_triangles)
        m_indices.insert(m_indices.end(), {slot(t.a), slot(t.b), slot(t.c)});

    // Immutable storage: grown (doubled) when a frame needs more, never shrunk.
    const std::size_t vertexBytes = m_vertices.size() * sizeof(Vertex);
    const std::size_t indexBytes = m_indices.size() * sizeof(std::uint32_t);
    if (!m_vertexBuffer.valid() || m_vertexBuffer.sizeBytes() < vertexBytes) {
        m_vertexBuffer = gl::Buffer::create(std::max<std::size_t>(2 * vertexBytes, 1 << 16),
                                            GL_DYNAMIC_STORAGE_BIT, "rtin vertices");
        m_vertexArray.setVertexBuffer(0, m_vertexBuffer, 0, sizeof(Vertex));
        m_vertexArray.setFloatAttribute(0, 0, 3, GL_FLOAT, false, offsetof(Vertex, sampleHeight));
        m_vertexArray.setFloatAttribute(1, 0, 3, GL_FLOAT, false, offsetof(Vertex, normal));
    }
    if (!m_indexBuffer.valid() || m_indexBuffer.sizeBytes() < indexBytes) {
        m_indexBuffer = gl::Buffer::create(std::max<std::size_t>(2 * indexBytes, 1 << 16),
                                           GL_DYNAMIC_STORAGE_BIT, "rtin indices");
        m_vertexArray.setIndexBuffer(m_indexBuffer);
    }
    if (vertexBytes > 0) m_vertexBuffer.upload(0, std::as_bytes(std::span(m_vertices)));
    if (indexBytes > 0) m_indexBuffer.upload(0, std::as_bytes(std::span(m_indices)));
}

TerrainDrawStats RtinStrategy::draw(const Camera& camera, const TerrainStyle& style) {
    const glm::dvec2 anchor = m_frame.bind(camera, style, m_errorPx);
    // Positions are relative to the anchor: written again only for a new mesh or anchor (the
    // accuracy probe, a frozen view, draw one frame more than once).
    if (!m_uploaded || anchor != m_uploadedAnchor) {
        upload(anchor);
        m_uploaded = true;
        m_uploadedAnchor = anchor;
    }
    TerrainDrawStats stats;
    stats.drawCalls = 1;
    stats.instances = 1;
    stats.triangles = m_triangles.size();
    {
        const gl::ReversedZScope reversedZ;
        if (style.wireframe) glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glUseProgram(m_program.id());
        glBindVertexArray(m_vertexArray.id());
        if (style.measure) m_timeQuery.begin();
        glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_indices.size()), GL_UNSIGNED_INT,
                       nullptr);
        if (style.measure) {
            m_timeQuery.end();
            stats.gpuMs = static_cast<double>(m_timeQuery.waitResult()) * 1.0e-6;
        }
        glBindVertexArray(0);
        glUseProgram(0);
        PlaneFrame::unbind();
        if (style.wireframe) glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
    m_lastDraw = stats;
    return stats;
}

void RtinStrategy::endFrame(FrameTelemetry& t) { writeDrawTelemetry(t, m_lodUpdateUs, m_lastDraw); }

std::uint64_t RtinStrategy::memoryBytes() const {
    return m_mesh.memoryBytes() + m_vertexBuffer.sizeBytes() + m_indexBuffer.sizeBytes();
}

}  // namespace terrain::runtime
