// Stage files -> linked program, with file:line errors.
#include "terrain/runtime/ProgramBuilder.h"

#include "terrain/gl/Shader.h"
#include "terrain/runtime/ShaderLog.h"

#include <epoxy/gl.h>

#include <utility>

namespace terrain::runtime {
namespace {

enum class ShaderStage { Vertex, TessControl, TessEvaluation, Geometry, Fragment, Compute };

/// By extension: .vert .tesc .tese .geom .frag .comp; std::nullopt otherwise.
std::optional<ShaderStage> shaderStageFromFileName(std::string_view fileName) {
    const std::size_t dot = fileName.rfind('.');
    if (dot == std::string_view::npos) {
        return std::nullopt;
    }
    const std::string_view extension = fileName.substr(dot + 1);
    if (extension == "vert") {
        return ShaderStage::Vertex;
    }
    if (extension == "tesc") {
        return ShaderStage::TessControl;
    }
    if (extension == "tese") {
        return ShaderStage::TessEvaluation;
    }
    if (extension == "geom") {
        return ShaderStage::Geometry;
    }
    if (extension == "frag") {
        return ShaderStage::Fragment;
    }
    if (extension == "comp") {
        return ShaderStage::Compute;
    }
    return std::nullopt;
}

GLenum glShaderType(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::Vertex:
            return GL_VERTEX_SHADER;
        case ShaderStage::TessControl:
            return GL_TESS_CONTROL_SHADER;
        case ShaderStage::TessEvaluation:
            return GL_TESS_EVALUATION_SHADER;
        case ShaderStage::Geometry:
            return GL_GEOMETRY_SHADER;
        case ShaderStage::Fragment:
            return GL_FRAGMENT_SHADER;
        case ShaderStage::Compute:
            return GL_COMPUTE_SHADER;
    }
    return GL_NONE;
}

}  // namespace

ProgramBuilder::ProgramBuilder(std::string label) : m_label(std::move(label)) {}

ProgramBuilder& ProgramBuilder::stage(std::string fileName) {
    m_stages.push_back({std::move(fileName), std::nullopt});
    return *this;
}

ProgramBuilder& ProgramBuilder::stageSource(std::string fileName, std::string text) {
    m_stages.push_back({std::move(fileName), std::move(text)});
    return *this;
}

ProgramBuilder& ProgramBuilder::define(std::string name, std::string value) {
    m_defines.push_back({std::move(name), std::move(value)});
    return *this;
}

ProgramBuilder& ProgramBuilder::loader(ShaderLoader loader) {
    m_loader = std::move(loader);
    return *this;
}

ProgramBuilder& ProgramBuilder::transformFeedback(std::vector<std::string> varyings) {
    m_feedbackVaryings = std::move(varyings);
    return *this;
}

Result<gl::Program> ProgramBuilder::build() const {
    const std::string name = "program '" + m_label + "'";
    if (m_stages.empty()) {
        return Error{name + ": no stages"};
    }
    const ShaderLoader loader = m_loader ? *m_loader : ShaderLoader::fromEnvironment();

    std::vector<gl::Shader> shaders;
    std::string stageList;
    for (const StageInput& input : m_stages) {
        const auto stage = shaderStageFromFileName(input.fileName);
        if (!stage) {
            return Error{name + ": " + input.fileName +
                         ": unknown stage (use .vert .tesc .tese .geom .frag .comp)"};
        }
        Result<ShaderFile> file =
            input.text ? Result<ShaderFile>(ShaderFile{input.fileName, input.fileName, *input.text})
                       : loader.load(input.fileName);
        if (!file) {
            return Error{name + ": " + file.error().message};
        }
        auto preprocessed = preprocessShader(file.value(), m_defines, loader);
        if (!preprocessed) {
            return Error{name + ": " + preprocessed.error().message};
        }

        gl::Shader shader =
            gl::Shader::create(glShaderType(*stage), m_label + "/" + input.fileName);
        if (!shader.compile(preprocessed.value().text)) {
            return Error{name + ": " + file.value().displayName + " failed to compile:\n" +
                         translateShaderLog(shader.infoLog(), preprocessed.value().sourceNames)};
        }
        stageList += (stageList.empty() ? "" : ", ") + file.value().displayName;
        shaders.push_back(std::move(shader));
    }

    gl::Program program = gl::Program::create(m_label);
    for (const gl::Shader& shader : shaders) {
        program.attach(shader);
    }
    if (!m_feedbackVaryings.empty()) {
        std::vector<const char*> names;
        for (const std::string& v : m_feedbackVaryings) names.push_back(v.c_str());
        glTransformFeedbackVaryings(program.id(), static_cast<GLsizei>(names.size()), names.data(),
                                    GL_INTERLEAVED_ATTRIBS);
    }
    const bool linked = program.link();
    // Detached shader objects are freed with `shaders`; the program keeps its binary.
    for (const gl::Shader& shader : shaders) {
        program.detach(shader);
    }
    if (!linked) {
        return Error{name + ": link failed (" + stageList + "):\n" + program.infoLog()};
    }
    return program;
}

}  // namespace terrain::runtime
