// ReferenceGrid: the mesh both reference renderers draw (ReferenceRenderer.h on the plane,
// GlobeReferenceRenderer.h on the globe): one grid of quads² cells as indexed triangles, each
// cell split along its north-west–south-east diagonal (vertex id = row · (quads + 1) + column),
// drawn as instances that read their heights from a texture array and their placement from a
// shader storage buffer.
#pragma once

#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Texture.h"
#include "terrain/gl/VertexArray.h"

#include <string_view>

namespace terrain::runtime {

class ReferenceGrid {
public:
    static ReferenceGrid create(int quads, std::string_view label);

    /// Draws `instanceCount` instances of the grid with `program`, `heights` bound at
    /// TERRAIN_BINDING_HEIGHTS and `instances` at TERRAIN_BINDING_PATCH_INSTANCES, and unbinds
    /// them again. Render thread only.
    void draw(const gl::Program& program, const gl::Texture& heights, const gl::Buffer& instances,
              int instanceCount) const;

private:
    gl::Buffer m_indices;
    gl::VertexArray m_vertexArray;
    int m_indexCount = 0;
};

}  // namespace terrain::runtime
