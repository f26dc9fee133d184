#include "terrain/runtime/PlaneFrame.h"

#include "Bindings.h"

#include <epoxy/gl.h>

namespace terrain::runtime {

PlaneFrame::PlaneFrame(const TerrainGeometry& geometry, const std::string& label)
    : m_placement(geometry), m_buffer(FrameBlockBuffer::create(label)) {}

glm::dvec2 PlaneFrame::bind(const Camera& camera, const TerrainStyle& style, double errorPx) {
    FrameBlock block;
    setCameraFrame(block, camera, camera, errorPx);
    m_placement.beginFrame(camera, block);
    setLook(block, style);
    m_buffer.upload(block);
    glBindBufferBase(GL_UNIFORM_BUFFER, TERRAIN_BINDING_FRAME_BLOCK, m_buffer.buffer().id());
    return m_placement.anchor();
}

void PlaneFrame::unbind() { glBindBufferBase(GL_UNIFORM_BUFFER, TERRAIN_BINDING_FRAME_BLOCK, 0); }

}  // namespace terrain::runtime
