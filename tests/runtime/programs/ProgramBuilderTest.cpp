// ProgramBuilder against a real driver: embedded and on-disk shaders, defines, includes,
// and compile / link errors that name the file and the line.
#include "GlTestFixture.h"
#include "TestSupport.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <string>

namespace terrain::test {
namespace {

class ProgramBuilderTest : public GlTest {
protected:
    /// The driver may also report a failed compile through debug output; a test that
    /// fails a compile on purpose clears those so the fixture does not count them.
    void forgetExpectedCompileErrors() { debugLog().clear(); }
};

constexpr std::string_view kVertex = R"glsl(
void main() {
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
)glsl";

TEST_F(ProgramBuilderTest, BuildsTessTestFromEmbeddedShaders) {
    ScopedEnv noOverride("TERRAIN_SHADER_DIR", "");
    auto program = runtime::ProgramBuilder("tess_test")
                       .stage("tess_test.vert")
                       .stage("tess_test.tesc")
                       .stage("tess_test.tese")
                       .stage("tess_test.frag")
                       .build();
    ASSERT_TRUE(program) << program.error().message;
    EXPECT_TRUE(program.value().valid());
    EXPECT_TRUE(program.value().hasUniform("u_outerLevels"));
    EXPECT_FALSE(program.value().hasUniform("u_noSuchUniform"));
}

TEST_F(ProgramBuilderTest, BuildsFromTheRealShaderFolderThroughTheEnvironment) {
    ScopedEnv shaderDir("TERRAIN_SHADER_DIR", TERRAIN_SOURCE_DIR "/shaders");
    auto program = runtime::ProgramBuilder("tess_test from disk")
                       .stage("tess_test.vert")
                       .stage("tess_test.tesc")
                       .stage("tess_test.tese")
                       .stage("tess_test.frag")
                       .build();
    ASSERT_TRUE(program) << program.error().message;
}

TEST_F(ProgramBuilderTest, CompileErrorInSourceTextNamesFileAndLine) {
    // Line 4 uses an undeclared name.
    const std::string fragment =
        "layout(location = 0) out vec4 o_color;\n"  // 1
        "void main() {\n"                           // 2
        "    o_color = vec4(1.0);\n"                // 3
        "    o_color.r = undeclaredThing;\n"        // 4
        "}\n";
    auto program = runtime::ProgramBuilder("broken")
                       .stageSource("ok.vert", std::string(kVertex))
                       .stageSource("broken.frag", fragment)
                       .build();
    forgetExpectedCompileErrors();
    ASSERT_FALSE(program);
    const std::string& message = program.error().message;
    EXPECT_TRUE(contains(message, "broken.frag:4:")) << message;
    EXPECT_TRUE(contains(message, "undeclaredThing")) << message;
    EXPECT_TRUE(contains(message, "program 'broken'")) << message;
}

TEST_F(ProgramBuilderTest, CompileErrorInFileOnDiskNamesPathAndLine) {
    TempDirectory folder;
    folder.write("plain.vert", kVertex);
    const auto path = folder.write("broken.frag",
                                   "// a comment\n"                            // 1
                                   "layout(location = 0) out vec4 o_color;\n"  // 2
                                   "\n"                                        // 3
                                   "void main() {\n"                           // 4
                                   "    o_color = vec4(1.0)\n"                 // 5: no ';'
                                   "    o_color.g = 0.5;\n"                    // 6
                                   "}\n");
    ScopedEnv shaderDir("TERRAIN_SHADER_DIR", folder.path().string());
    auto program =
        runtime::ProgramBuilder("broken on disk").stage("plain.vert").stage("broken.frag").build();
    forgetExpectedCompileErrors();
    ASSERT_FALSE(program);
    const std::string& message = program.error().message;
    // A missing ';' is reported where the parser notices it: line 5 or 6.
    EXPECT_TRUE(contains(message, path.string() + ":5:") ||
                contains(message, path.string() + ":6:"))
        << message;
}

TEST_F(ProgramBuilderTest, ErrorsInsideAndAfterAnIncludeKeepTheirFilesAndLines) {
    TempDirectory folder;
    folder.write("plain.vert", kVertex);
    const auto common = folder.write("Common.glsl",
                                     "// shared helpers\n"        // 1
                                     "float helper() {\n"         // 2
                                     "    return missingName;\n"  // 3
                                     "}\n");
    const auto broken = folder.write("broken.frag",
                                     "#include \"Common.glsl\"\n"                               // 1
                                     "layout(location = 0) out vec4 o_color;\n"                 // 2
                                     "void main() {\n"                                          // 3
                                     "    o_color = vec4(helper(), otherMissing, 0.0, 1.0);\n"  // 4
                                     "}\n");
    auto program = runtime::ProgramBuilder("include errors")
                       .loader(runtime::ShaderLoader(folder.path()))
                       .stage("plain.vert")
                       .stage("broken.frag")
                       .build();
    forgetExpectedCompileErrors();
    ASSERT_FALSE(program);
    const std::string& message = program.error().message;
    EXPECT_TRUE(contains(message, common.string() + ":3:")) << message;
    EXPECT_TRUE(contains(message, broken.string() + ":4:")) << message;
    // Line 3 of the stage file is fine: an error there would mean the include's error was
    // attributed to the wrong file (Mesa reports source string 0 for it).
    EXPECT_FALSE(contains(message, broken.string() + ":3:")) << message;
}

TEST_F(ProgramBuilderTest, DefinesReachEveryStage) {
    const std::string fragment =
        "#ifndef TERRAIN_TEST_COLOUR\n"            // 1
        "#error TERRAIN_TEST_COLOUR is missing\n"  // 2
        "#endif\n"                                 // 3
        "layout(location = 0) out vec4 o_color;\n"
        "void main() { o_color = TERRAIN_TEST_COLOUR; }\n";
    auto withDefine = runtime::ProgramBuilder("with define")
                          .define("TERRAIN_TEST_COLOUR", "vec4(1.0, 0.0, 0.0, 1.0)")
                          .stageSource("plain.vert", std::string(kVertex))
                          .stageSource("define.frag", fragment)
                          .build();
    ASSERT_TRUE(withDefine) << withDefine.error().message;

    auto withoutDefine = runtime::ProgramBuilder("without define")
                             .stageSource("plain.vert", std::string(kVertex))
                             .stageSource("define.frag", fragment)
                             .build();
    forgetExpectedCompileErrors();
    ASSERT_FALSE(withoutDefine);
    EXPECT_TRUE(contains(withoutDefine.error().message, "define.frag:2:"))
        << withoutDefine.error().message;
}

TEST_F(ProgramBuilderTest, LinkErrorIsReportedWithTheStages) {
    // The fragment stage reads an input no earlier stage writes.
    const std::string fragment =
        "in vec4 i_neverWritten;\n"
        "layout(location = 0) out vec4 o_color;\n"
        "void main() { o_color = i_neverWritten; }\n";
    auto program = runtime::ProgramBuilder("link error")
                       .stageSource("plain.vert", std::string(kVertex))
                       .stageSource("reads.frag", fragment)
                       .build();
    forgetExpectedCompileErrors();
    ASSERT_FALSE(program);
    EXPECT_TRUE(contains(program.error().message, "link failed")) << program.error().message;
    EXPECT_TRUE(contains(program.error().message, "reads.frag")) << program.error().message;
}

TEST_F(ProgramBuilderTest, MissingFileAndUnknownStageAreErrors) {
    ScopedEnv noOverride("TERRAIN_SHADER_DIR", "");
    auto missing = runtime::ProgramBuilder("missing").stage("no_such_shader.frag").build();
    ASSERT_FALSE(missing);
    EXPECT_TRUE(contains(missing.error().message, "no_such_shader.frag"))
        << missing.error().message;

    auto unknown = runtime::ProgramBuilder("unknown").stage("Bindings.h").build();
    ASSERT_FALSE(unknown);
    EXPECT_TRUE(contains(unknown.error().message, "unknown stage")) << unknown.error().message;
}

TEST_F(ProgramBuilderTest, VersionLineInAFileIsAnError) {
    auto program = runtime::ProgramBuilder("version")
                       .stageSource("versioned.vert", "#version 330 core\nvoid main() {}\n")
                       .build();
    ASSERT_FALSE(program);
    EXPECT_TRUE(contains(program.error().message, "versioned.vert:1:")) << program.error().message;
}

}  // namespace
}  // namespace terrain::test
