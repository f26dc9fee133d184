#include "PreviewRenderer.h"

#include "Bindings.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>

namespace terrain::tools {
namespace {

constexpr std::array<float, 4> kSkyColor{0.72f, 0.80f, 0.90f, 1.0f};

std::array<float, 3> toArray(const glm::dvec3& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

}  // namespace

io::Result<PreviewRenderer> PreviewRenderer::create(std::span<const float> heights, int side,
                                                    double sampleSpacingM,
                                                    const PreviewView& view) {
    if (side < kPatchQuads + 1 || (side - 1) % kPatchQuads != 0)
        return io::Error{"preview: the DEM side must be k·" + std::to_string(kPatchQuads) +
                         " + 1 samples (got " + std::to_string(side) + ")"};
    TERRAIN_ASSERT(heights.size() == static_cast<std::size_t>(side) * side);

    PreviewRenderer r;
    r.m_view = view;
    r.m_side = side;
    r.m_sampleSpacingM = sampleSpacingM;
    const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
    r.m_minHeightM = *lo;
    r.m_maxHeightM = *hi;

    auto texture = gl::Texture::create2D({GL_R32F, side, side, 1, 1}, "preview heights");
    if (!texture) return texture.error();
    r.m_heights = std::move(texture).value();
    r.m_heights.upload(r.m_heights.wholeLevel(), GL_RED, GL_FLOAT, std::as_bytes(heights));
    r.m_heights.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);

    auto framebuffer = gl::Framebuffer::create(view.widthPx, view.heightPx, "preview frame");
    if (!framebuffer) return framebuffer.error();
    r.m_framebuffer = std::move(framebuffer).value();

    auto program = runtime::ProgramBuilder("preview terrain")
                       .stage("preview_terrain.vert")
                       .stage("preview_terrain.tesc")
                       .stage("preview_terrain.tese")
                       .stage("preview_terrain.frag")
                       .build();
    if (!program) return program.error();
    r.m_program = std::move(program).value();
    r.m_vertexArray = gl::VertexArray::create("preview patches (attribute-less)");

    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, "preview triangles");
    if (!primitives) return primitives.error();
    r.m_primitives = std::move(primitives).value();
    auto timer = gl::Query::create(gl::QueryKind::TimeElapsed, "preview draw time");
    if (!timer) return timer.error();
    r.m_timer = std::move(timer).value();
    return r;
}

PreviewFrame PreviewRenderer::render() {
    // An oblique view from the south-south-west that frames the whole DEM: 30° pitch,
    // far enough that the DEM's diagonal fits the vertical field of view.
    const double extentM = (m_side - 1) * m_sampleSpacingM;
    const double fovY = m_view.fovYDegrees * std::numbers::pi / 180.0;
    const double distanceM = 0.45 * extentM / std::tan(0.5 * fovY);
    const double pitch = 30.0 * std::numbers::pi / 180.0;
    const double yaw = 20.0 * std::numbers::pi / 180.0;  // from south, towards west
    const double centre = 0.5 * (m_side - 1);
    const double targetHeightM = 0.5 * (m_minHeightM + m_maxHeightM);
    // Camera in (samples east, metres up, samples south); direction in metres.
    const glm::dvec3 towardCamera{-std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                  std::cos(yaw) * std::cos(pitch)};
    const glm::dvec3 cameraSample{centre + towardCamera.x * distanceM / m_sampleSpacingM,
                                  targetHeightM + towardCamera.y * distanceM,
                                  centre + towardCamera.z * distanceM / m_sampleSpacingM};
    const double aspect = double(m_view.widthPx) / m_view.heightPx;
    const glm::dmat4 projection =
        glm::perspective(fovY, aspect, 0.001 * distanceM, 4.0 * distanceM);
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), -towardCamera, glm::dvec3(0, 1, 0));
    const glm::mat4 viewProjection(projection * view);  // camera-relative: no translation
    const double gammaPx = 0.5 * m_view.heightPx / std::tan(0.5 * fovY);

    const int patchesPerSide = (m_side - 1) / kPatchQuads;
    m_program.setUniform("u_patchesPerSide", patchesPerSide);
    m_program.setUniform("u_patchQuads", kPatchQuads);
    m_program.setUniform("u_cameraSample", toArray(cameraSample));
    m_program.setUniform("u_sampleSpacingM", static_cast<float>(m_sampleSpacingM));
    m_program.setUniform("u_gammaPx", static_cast<float>(gammaPx));
    m_program.setUniform("u_pixelsPerSegment", m_view.pixelsPerSegment);
    m_program.setUniformMat4("u_viewProjection",
                             std::span<const float, 16>(glm::value_ptr(viewProjection), 16));
    m_program.setUniform("u_sunDirection", toArray(glm::normalize(glm::dvec3(-1.0, 1.2, -1.0))));
    m_program.setUniform("u_heightRangeM", std::array<float, 2>{m_minHeightM, m_maxHeightM});
    m_program.setUniform("u_skyColor",
                         std::array<float, 3>{kSkyColor[0], kSkyColor[1], kSkyColor[2]});
    m_program.setUniform("u_fogDensityPerM", static_cast<float>(0.6 / (4.0 * distanceM)));

    m_framebuffer.clear(kSkyColor);
    glBindFramebuffer(GL_FRAMEBUFFER, m_framebuffer.id());
    glViewport(0, 0, m_view.widthPx, m_view.heightPx);
    glEnable(GL_DEPTH_TEST);
    glUseProgram(m_program.id());
    glBindVertexArray(m_vertexArray.id());
    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, m_heights.id());
    glPatchParameteri(GL_PATCH_VERTICES, 4);

    m_timer.begin();
    m_primitives.begin();
    glDrawArraysInstanced(GL_PATCHES, 0, 4, patchesPerSide * patchesPerSide);
    m_primitives.end();
    m_timer.end();

    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, 0);
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    PreviewFrame frame;
    frame.patches = patchesPerSide * patchesPerSide;
    frame.trianglesGenerated = m_primitives.waitResult();
    frame.gpuMs = static_cast<double>(m_timer.waitResult()) * 1e-6;
    // GL rows are bottom-up; images are top-down.
    const std::vector<std::uint8_t> bottomUp = m_framebuffer.readColorRgba8();
    const std::size_t rowBytes = static_cast<std::size_t>(m_view.widthPx) * 4;
    frame.rgba.resize(bottomUp.size());
    for (int y = 0; y < m_view.heightPx; ++y)
        std::memcpy(frame.rgba.data() + y * rowBytes,
                    bottomUp.data() + (m_view.heightPx - 1 - y) * rowBytes, rowBytes);
    return frame;
}

}  // namespace terrain::tools
