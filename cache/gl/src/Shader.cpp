// Shader stage objects.
#include "terrain/gl/Shader.h"

#include "terrain/base/Assert.h"

namespace terrain::gl {

Shader Shader::create(GLenum stage, std::string_view label) {
    Shader shader;
    shader.m_stage = stage;
    shader.m_handle = ShaderHandle(glCreateShader(stage));
    TERRAIN_ASSERT(shader.valid(), "glCreateShader failed: unknown stage or no current context");
    shader.m_handle.setLabel(label);
    return shader;
}

bool Shader::compile(std::string_view source) {
    TERRAIN_ASSERT(valid());
    const GLchar* text = source.data();
    const auto length = static_cast<GLint>(source.size());
    glShaderSource(id(), 1, &text, &length);
    glCompileShader(id());
    GLint status = GL_FALSE;
    glGetShaderiv(id(), GL_COMPILE_STATUS, &status);
    return status == GL_TRUE;
}

std::string Shader::infoLog() const {
    TERRAIN_ASSERT(valid());
    GLint length = 0;
    glGetShaderiv(id(), GL_INFO_LOG_LENGTH, &length);
    if (length <= 1) {
        return {};
    }
    std::string log(static_cast<std::size_t>(length), '\0');
    GLsizei written = 0;
    glGetShaderInfoLog(id(), length, &written, log.data());
    log.resize(static_cast<std::size_t>(written));
    return log;
}

}  // namespace terrain::gl
