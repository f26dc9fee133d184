// Program: a linked GL program object, with cached uniform lookup and DSA uniform setters
// (glProgramUniform*), so setting a uniform never needs the program bound.
#pragma once

#include "terrain/gl/Handle.h"
#include "terrain/gl/Shader.h"

#include <array>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>

namespace terrain::gl {

class Program {
public:
    Program() = default;

    /// An empty program object. Render thread only.
    static Program create(std::string_view label = {});

    /// Render thread only.
    void attach(const Shader& shader);
    void detach(const Shader& shader);

    /// Links the attached shaders; false on failure, with the driver's messages in
    /// infoLog(). Render thread only.
    bool link();

    /// The driver's link log. Render thread only.
    std::string infoLog() const;

    /// Location of an active uniform, -1 when the program has none of that name (also
    /// when the compiler removed it as unused). Cached per name. Render thread only.
    GLint uniformLocation(std::string_view name) const;
    bool hasUniform(std::string_view name) const { return uniformLocation(name) >= 0; }

    /// Uniform setters. Like GL itself, a name with no active uniform is ignored: unused
    /// uniforms are legitimately removed by compilers. Render thread only.
    void setUniform(std::string_view name, int value);
    void setUniform(std::string_view name, unsigned value);
    void setUniform(std::string_view name, float value);
    void setUniform(std::string_view name, const std::array<float, 2>& value);
    void setUniform(std::string_view name, const std::array<int, 2>& value);
    void setUniform(std::string_view name, const std::array<float, 3>& value);
    void setUniform(std::string_view name, const std::array<float, 4>& value);
    /// A vec4[] uniform from element 0: values.size() / 4 vectors (a multiple of 4 floats).
    void setUniformVec4Array(std::string_view name, std::span<const float> values);
    /// A column-major 4x4 matrix.
    void setUniformMat4(std::string_view name, std::span<const float, 16> columnMajor);

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }
    const std::string& label() const { return m_label; }

private:
    struct NameHash {
        using is_transparent = void;
        std::size_t operator()(std::string_view name) const {
            return std::hash<std::string_view>{}(name);
        }
    };

    ProgramHandle m_handle;
    std::string m_label;
    mutable std::unordered_map<std::string, GLint, NameHash, std::equal_to<>> m_uniformLocations;
};

}  // namespace terrain::gl
