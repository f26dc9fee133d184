// Program objects: linking, uniform lookup, DSA uniform setters.
#include "terrain/gl/Program.h"

#include "terrain/base/Assert.h"

namespace terrain::gl {

Program Program::create(std::string_view label) {
    Program program;
    program.m_handle = ProgramHandle(glCreateProgram());
    TERRAIN_ASSERT(program.valid(), "glCreateProgram failed: no current context");
    program.m_label = std::string(label);
    program.m_handle.setLabel(label);
    return program;
}

void Program::attach(const Shader& shader) {
    TERRAIN_ASSERT(valid() && shader.valid());
    glAttachShader(id(), shader.id());
}

void Program::detach(const Shader& shader) {
    TERRAIN_ASSERT(valid() && shader.valid());
    glDetachShader(id(), shader.id());
}

bool Program::link() {
    TERRAIN_ASSERT(valid());
    m_uniformLocations.clear();  // locations change with every link
    glLinkProgram(id());
    GLint status = GL_FALSE;
    glGetProgramiv(id(), GL_LINK_STATUS, &status);
    return status == GL_TRUE;
}

std::string Program::infoLog() const {
    TERRAIN_ASSERT(valid());
    GLint length = 0;
    glGetProgramiv(id(), GL_INFO_LOG_LENGTH, &length);
    if (length <= 1) {
        return {};
    }
    std::string log(static_cast<std::size_t>(length), '\0');
    GLsizei written = 0;
    glGetProgramInfoLog(id(), length, &written, log.data());
    log.resize(static_cast<std::size_t>(written));
    return log;
}

GLint Program::uniformLocation(std::string_view name) const {
    TERRAIN_ASSERT(valid());
    if (auto found = m_uniformLocations.find(name); found != m_uniformLocations.end()) {
        return found->second;
    }
    const std::string key(name);
    const GLint location = glGetUniformLocation(id(), key.c_str());
    m_uniformLocations.emplace(key, location);
    return location;
}

void Program::setUniform(std::string_view name, int value) {
    glProgramUniform1i(id(), uniformLocation(name), value);
}

void Program::setUniform(std::string_view name, unsigned value) {
    glProgramUniform1ui(id(), uniformLocation(name), value);
}

void Program::setUniform(std::string_view name, float value) {
    glProgramUniform1f(id(), uniformLocation(name), value);
}

void Program::setUniform(std::string_view name, const std::array<float, 2>& value) {
    glProgramUniform2fv(id(), uniformLocation(name), 1, value.data());
}

void Program::setUniform(std::string_view name, const std::array<int, 2>& value) {
    glProgramUniform2iv(id(), uniformLocation(name), 1, value.data());
}

void Program::setUniform(std::string_view name, const std::array<float, 3>& value) {
    glProgramUniform3fv(id(), uniformLocation(name), 1, value.data());
}

void Program::setUniform(std::string_view name, const std::array<float, 4>& value) {
    glProgramUniform4fv(id(), uniformLocation(name), 1, value.data());
}

void Program::setUniformVec4Array(std::string_view name, std::span<const float> values) {
    TERRAIN_ASSERT(values.size() % 4 == 0, "Program::setUniformVec4Array: not whole vec4s");
    glProgramUniform4fv(id(), uniformLocation(name), static_cast<GLsizei>(values.size() / 4),
                        values.data());
}

void Program::setUniformMat4(std::string_view name, std::span<const float, 16> columnMajor) {
    glProgramUniformMatrix4fv(id(), uniformLocation(name), 1, GL_FALSE, columnMajor.data());
}

}  // namespace terrain::gl
