// PreviewRenderer: draws one height raster (a whole small DEM in one texture) as a grid
// of tessellated patches with a hillshade, headless, into an offscreen framebuffer.
// The stand-in main job until the pyramid, streaming and the LOD tree exist.
#pragma once

#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/Texture.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/io/Result.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace terrain::tools {

struct PreviewView {
    int widthPx = 1280;
    int heightPx = 720;
    double fovYDegrees = 45.0;
    float pixelsPerSegment = 6.0f;  ///< target projected length of a triangle edge
};

struct PreviewFrame {
    std::vector<std::uint8_t> rgba;        ///< rows top to bottom
    std::uint64_t trianglesGenerated = 0;  ///< GL_PRIMITIVES_GENERATED
    double gpuMs = 0.0;                    ///< GL_TIME_ELAPSED of the draw
    int patches = 0;
};

class PreviewRenderer {
public:
    /// `heights` is side × side, row-major, row 0 north; side − 1 must be a multiple of
    /// kPatchQuads. Render thread only.
    static io::Result<PreviewRenderer> create(std::span<const float> heights, int side,
                                              double sampleSpacingM, const PreviewView& view);

    /// Renders the DEM from an oblique camera that frames all of it. Render thread only.
    PreviewFrame render();

    static constexpr int kPatchQuads = 64;

private:
    PreviewRenderer() = default;

    gl::Texture m_heights;
    gl::Framebuffer m_framebuffer;
    gl::Program m_program;
    gl::VertexArray m_vertexArray;
    gl::Query m_primitives;
    gl::Query m_timer;
    PreviewView m_view;
    int m_side = 0;
    double m_sampleSpacingM = 1.0;
    float m_minHeightM = 0.0f;
    float m_maxHeightM = 0.0f;
};

}  // namespace terrain::tools
