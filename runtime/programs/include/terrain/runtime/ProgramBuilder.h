// ProgramBuilder: the one way programs are made. Takes stage files by name (the stage
// comes from the extension), loads them (embedded, or TERRAIN_SHADER_DIR), prepends
// `#version 450 core` and defines, resolves #include, and reports compile and link errors
// as "<file>:<line>: ..." in an Error.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Program.h"
#include "terrain/runtime/ShaderLoader.h"
#include "terrain/runtime/ShaderPreprocessor.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace terrain::runtime {

class ProgramBuilder {
public:
    /// `label` names the program in messages and GL debug labels.
    explicit ProgramBuilder(std::string label);

    /// A stage file, read through the loader when build() runs.
    ProgramBuilder& stage(std::string fileName);

    /// A stage whose text is given; `fileName` picks the stage and names it in messages.
    /// Its includes still come from the loader.
    ProgramBuilder& stageSource(std::string fileName, std::string text);

    /// `#define name value`, after the #version line, in every stage.
    ProgramBuilder& define(std::string name, std::string value = "1");

    /// Output variables the last vertex-processing stage writes to transform feedback
    /// buffer 0, interleaved in this order (glTransformFeedbackVaryings before the link).
    ProgramBuilder& transformFeedback(std::vector<std::string> varyings);

    /// Where files come from; default ShaderLoader::fromEnvironment().
    ProgramBuilder& loader(ShaderLoader loader);

    /// Loads, preprocesses, compiles and links. Render thread only.
    Result<gl::Program> build() const;

private:
    struct StageInput {
        std::string fileName;
        std::optional<std::string> text;  ///< set by stageSource()
    };

    std::string m_label;
    std::vector<StageInput> m_stages;
    std::vector<ShaderDefine> m_defines;
    std::vector<std::string> m_feedbackVaryings;
    std::optional<ShaderLoader> m_loader;
};

}  // namespace terrain::runtime
