// Vertex array objects through DSA.
#include "terrain/gl/VertexArray.h"

#include "terrain/base/Assert.h"

namespace terrain::gl {

VertexArray VertexArray::create(std::string_view label) {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    VertexArray vertexArray;
    vertexArray.m_handle = VertexArrayHandle(id);
    vertexArray.m_handle.setLabel(label);
    return vertexArray;
}

void VertexArray::setVertexBuffer(GLuint bindingIndex, const Buffer& buffer,
                                  std::size_t offsetBytes, std::size_t strideBytes) {
    TERRAIN_ASSERT(valid() && buffer.valid());
    glVertexArrayVertexBuffer(id(), bindingIndex, buffer.id(), static_cast<GLintptr>(offsetBytes),
                              static_cast<GLsizei>(strideBytes));
}

void VertexArray::setFloatAttribute(GLuint location, GLuint bindingIndex, int components,
                                    GLenum type, bool normalized, std::size_t relativeOffsetBytes) {
    TERRAIN_ASSERT(valid());
    glEnableVertexArrayAttrib(id(), location);
    glVertexArrayAttribFormat(id(), location, components, type, normalized ? GL_TRUE : GL_FALSE,
                              static_cast<GLuint>(relativeOffsetBytes));
    glVertexArrayAttribBinding(id(), location, bindingIndex);
}

void VertexArray::setIndexBuffer(const Buffer& buffer) {
    TERRAIN_ASSERT(valid() && buffer.valid());
    glVertexArrayElementBuffer(id(), buffer.id());
}

}  // namespace terrain::gl
