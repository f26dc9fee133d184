// Shader: one compiled shader stage object. Programs are built from these by the runtime's
// ProgramBuilder, which also turns the driver's log into file:line messages.
#pragma once

#include "terrain/gl/Handle.h"

#include <string>
#include <string_view>

namespace terrain::gl {

class Shader {
public:
    Shader() = default;

    /// An empty shader object of `stage` (GL_VERTEX_SHADER, ...). Render thread only.
    static Shader create(GLenum stage, std::string_view label = {});

    /// Compiles `source`; false on failure, with the driver's messages in infoLog().
    /// Render thread only.
    bool compile(std::string_view source);

    /// The driver's compile log, as it printed it. Render thread only.
    std::string infoLog() const;

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }
    GLenum stage() const { return m_stage; }

private:
    ShaderHandle m_handle;
    GLenum m_stage = GL_NONE;
};

}  // namespace terrain::gl
