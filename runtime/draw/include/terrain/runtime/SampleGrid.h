// SampleGrid: one grid of quads² cells of samples as indexed triangles, each cell split along
// its north-west–south-east diagonal (vertex id = row · (quads + 1) + column), drawn as
// instances that read their heights from a texture array and their placement from a shader
// storage buffer: the mesh of the reference renderer (ReferenceRenderer.h, on the plane and
// the globe) and of CDLOD's patches (CdlodRenderer.h).
#pragma once

#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Texture.h"
#include "terrain/gl/VertexArray.h"

#include <string_view>

namespace terrain::runtime {

class SampleGrid {
public:
    static SampleGrid create(int quads, std::string_view label);

    /// Draws `instanceCount` instances of the grid with `program`, `heights` bound at
    /// TERRAIN_BINDING_HEIGHTS and `instances` at TERRAIN_BINDING_PATCH_INSTANCES, and unbinds
    /// them again. Render thread only.
    void draw(const gl::Program& program, const gl::Texture& heights, const gl::Buffer& instances,
              int instanceCount) const;

    /// The vertex array holding the index buffer, and its indices: for draws that bind the
    /// rest themselves (issueInstancedPatchDraw).
    const gl::VertexArray& vertexArray() const { return m_vertexArray; }
    int indexCount() const { return m_indexCount; }

private:
    gl::Buffer m_indices;
    gl::VertexArray m_vertexArray;
    int m_indexCount = 0;
};

}  // namespace terrain::runtime
