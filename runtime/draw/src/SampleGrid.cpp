#include "terrain/runtime/SampleGrid.h"

#include "Bindings.h"

#include <epoxy/gl.h>

#include <cstdint>
#include <string>
#include <vector>

namespace terrain::runtime {

SampleGrid SampleGrid::create(int quads, std::string_view label) {
    const int samples = quads + 1;
    std::vector<std::uint32_t> indices;
    indices.reserve(static_cast<std::size_t>(quads) * static_cast<std::size_t>(quads) * 6);
    for (int j = 0; j < quads; ++j) {
        for (int i = 0; i < quads; ++i) {
            const auto nw = static_cast<std::uint32_t>(j * samples + i);
            const std::uint32_t ne = nw + 1;
            const auto sw = static_cast<std::uint32_t>(nw + static_cast<std::uint32_t>(samples));
            const std::uint32_t se = sw + 1;
            indices.insert(indices.end(), {nw, ne, se, nw, se, sw});
        }
    }
    SampleGrid grid;
    grid.m_indexCount = static_cast<int>(indices.size());
    grid.m_indices = gl::Buffer::createFrom(std::span<const std::uint32_t>(indices), 0,
                                            std::string(label) + " indices");
    grid.m_vertexArray = gl::VertexArray::create(label);
    grid.m_vertexArray.setIndexBuffer(grid.m_indices);
    return grid;
}

void SampleGrid::draw(const gl::Program& program, const gl::Texture& heights,
                      const gl::Buffer& instances, int instanceCount) const {
    glUseProgram(program.id());
    glBindVertexArray(m_vertexArray.id());
    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, heights.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES, instances.id());
    glDrawElementsInstanced(GL_TRIANGLES, m_indexCount, GL_UNSIGNED_INT, nullptr, instanceCount);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES, 0);
    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, 0);
    glBindVertexArray(0);
    glUseProgram(0);
}

}  // namespace terrain::runtime
