// preprocessShader: #version and defines first, includes inlined with #line bookkeeping,
// and errors that name file and line.
#include "TestSupport.h"
#include "terrain/runtime/ShaderPreprocessor.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace terrain::test {
namespace {

runtime::ShaderFile file(std::string name, std::string text) {
    return {name, name, std::move(text)};
}

TEST(ShaderPreprocessor, VersionDefinesAndLineComeFirst) {
    const std::vector<runtime::ShaderDefine> defines = {{"TERRAIN_A", "1"}, {"TERRAIN_B", ""}};
    auto result = runtime::preprocessShader(file("x.vert", "void main() {}\n"), defines,
                                            runtime::ShaderLoader());
    ASSERT_TRUE(result) << result.error().message;
    EXPECT_EQ(result.value().text,
              "#version 450 core\n"
              "#define TERRAIN_A 1\n"
              "#define TERRAIN_B\n"
              "#line 1 0\n"
              "void main() {}\n");
    EXPECT_EQ(result.value().sourceNames, std::vector<std::string>{"x.vert"});
}

TEST(ShaderPreprocessor, IncludesAreInlinedWithLineDirectives) {
    TempDirectory folder;
    folder.write("A.glsl", "// a\nfloat a() { return 1.0; }");  // no final newline
    folder.write("B.glsl", "#include \"A.glsl\"\nfloat b() { return a(); }\n");
    const runtime::ShaderLoader loader(folder.path());
    auto result = runtime::preprocessShader(
        file("main.frag",
             "// main\n#include \"B.glsl\"  // helpers\n  #  include \"A.glsl\"\nvoid main() {}\n"),
        {}, loader);
    ASSERT_TRUE(result) << result.error().message;
    const std::string a = (folder.path() / "A.glsl").string();
    const std::string b = (folder.path() / "B.glsl").string();
    EXPECT_EQ(result.value().sourceNames, (std::vector<std::string>{"main.frag", b, a}));
    EXPECT_EQ(result.value().text,
              "#version 450 core\n"
              "#line 1 0\n"
              "// main\n"
              "#line 100001 1\n"
              "#line 200001 2\n"
              "// a\n"
              "float a() { return 1.0; }\n"
              "#line 100002 1\n"
              "float b() { return a(); }\n"
              "#line 3 0\n"
              "#line 200001 2\n"
              "// a\n"
              "float a() { return 1.0; }\n"
              "#line 4 0\n"
              "void main() {}\n");
}

TEST(ShaderPreprocessor, EmbeddedBindingsHeaderIsIncludable) {
    auto result = runtime::preprocessShader(file("x.frag", "#include \"Bindings.h\"\n"), {},
                                            runtime::ShaderLoader());
    ASSERT_TRUE(result) << result.error().message;
    EXPECT_TRUE(contains(result.value().text, "#define TERRAIN_BINDING_HEIGHTS"));
    EXPECT_EQ(result.value().sourceNames, (std::vector<std::string>{"x.frag", "Bindings.h"}));
}

TEST(ShaderPreprocessor, ErrorsNameFileAndLine) {
    TempDirectory folder;
    folder.write("Loop.glsl", "// loop\n#include \"Loop.glsl\"\n");
    const runtime::ShaderLoader loader(folder.path());

    auto missing =
        runtime::preprocessShader(file("m.frag", "\n\n#include \"Nope.glsl\"\n"), {}, loader);
    ASSERT_FALSE(missing);
    EXPECT_TRUE(contains(missing.error().message, "m.frag:3:")) << missing.error().message;
    EXPECT_TRUE(contains(missing.error().message, "Nope.glsl")) << missing.error().message;

    auto cycle = runtime::preprocessShader(file("c.frag", "#include \"Loop.glsl\"\n"), {}, loader);
    ASSERT_FALSE(cycle);
    EXPECT_TRUE(contains(cycle.error().message, "include cycle")) << cycle.error().message;
    EXPECT_TRUE(contains(cycle.error().message, "Loop.glsl:2:")) << cycle.error().message;

    auto angle = runtime::preprocessShader(file("a.frag", "#include <Bindings.h>\n"), {}, loader);
    ASSERT_FALSE(angle);
    EXPECT_TRUE(contains(angle.error().message, "a.frag:1:")) << angle.error().message;

    auto version = runtime::preprocessShader(file("v.frag", "\n#version 460\n"), {}, loader);
    ASSERT_FALSE(version);
    EXPECT_TRUE(contains(version.error().message, "v.frag:2:")) << version.error().message;

    const std::vector<runtime::ShaderDefine> badDefine = {{"2BAD", "1"}};
    EXPECT_FALSE(runtime::preprocessShader(file("d.frag", ""), badDefine, loader));
    const std::vector<runtime::ShaderDefine> multiLine = {{"GOOD", "1\n#define EVIL"}};
    EXPECT_FALSE(runtime::preprocessShader(file("d.frag", ""), multiLine, loader));
}

TEST(ShaderPreprocessor, SimilarDirectivesAreNotIncludes) {
    auto result = runtime::preprocessShader(
        file("s.frag", "#includes_nothing\n// #include \"Nope.glsl\"\n#define versioned 1\n"), {},
        runtime::ShaderLoader());
    ASSERT_TRUE(result) << result.error().message;
}

}  // namespace
}  // namespace terrain::test
