// VertexArray: a vertex array object set up through DSA (glVertexArray*), so describing
// the vertex layout never disturbs the bound VAO. Core profile draws need one bound even
// when the vertex shader reads no attributes.
#pragma once

#include "terrain/gl/Buffer.h"
#include "terrain/gl/Handle.h"

#include <cstddef>
#include <string_view>

namespace terrain::gl {

class VertexArray {
public:
    VertexArray() = default;

    /// Render thread only.
    static VertexArray create(std::string_view label = {});

    /// Attaches `buffer` to binding slot `bindingIndex` (glVertexArrayVertexBuffer).
    /// The VAO refers to the buffer by name: keep the Buffer alive while drawing.
    void setVertexBuffer(GLuint bindingIndex, const Buffer& buffer, std::size_t offsetBytes,
                         std::size_t strideBytes);

    /// Enables float attribute `location` read from binding slot `bindingIndex`.
    void setFloatAttribute(GLuint location, GLuint bindingIndex, int components, GLenum type,
                           bool normalized, std::size_t relativeOffsetBytes);

    /// Element (index) buffer for glDrawElements*.
    void setIndexBuffer(const Buffer& buffer);

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }

private:
    VertexArrayHandle m_handle;
};

}  // namespace terrain::gl
