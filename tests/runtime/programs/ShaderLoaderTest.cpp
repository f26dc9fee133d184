// ShaderLoader and the embedded shader table: every file of shaders/ is embedded byte for
// byte, and TERRAIN_SHADER_DIR replaces the table with a folder.
#include "TestSupport.h"
#include "terrain/runtime/EmbeddedShaders.h"
#include "terrain/runtime/ShaderLoader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace terrain::test {
namespace {

const std::filesystem::path kShaderFolder = TERRAIN_SOURCE_DIR "/shaders";

std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(EmbeddedShaders, EveryShaderFileIsEmbeddedVerbatim) {
    const std::set<std::string> extensions = {".vert", ".tesc", ".tese", ".geom",
                                              ".frag", ".comp", ".glsl", ".h"};
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(kShaderFolder)) {
        if (!extensions.contains(entry.path().extension().string())) {
            continue;
        }
        ++files;
        const std::string name = entry.path().filename().string();
        const runtime::EmbeddedShader* shader = runtime::findEmbeddedShader(name);
        ASSERT_NE(shader, nullptr) << name << " is not embedded";
        EXPECT_EQ(shader->source, readFile(entry.path())) << name << " differs from its file";
    }
    EXPECT_GE(files, 5);
    EXPECT_EQ(runtime::embeddedShaders().size(), static_cast<std::size_t>(files));
    EXPECT_EQ(runtime::findEmbeddedShader("no_such.vert"), nullptr);
}

TEST(ShaderLoader, EmbeddedByDefault) {
    auto loaded = runtime::ShaderLoader().load("tess_test.vert");
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded.value().displayName, "tess_test.vert");
    EXPECT_EQ(loaded.value().text, readFile(kShaderFolder / "tess_test.vert"));
}

TEST(ShaderLoader, EnvironmentFolderReplacesTheTable) {
    TempDirectory folder;
    const auto path = folder.write("tess_test.vert", "// edited\n");
    {
        ScopedEnv shaderDir("TERRAIN_SHADER_DIR", folder.path().string());
        const runtime::ShaderLoader loader = runtime::ShaderLoader::fromEnvironment();
        ASSERT_TRUE(loader.directory().has_value());
        auto loaded = loader.load("tess_test.vert");
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded.value().text, "// edited\n");
        EXPECT_EQ(loaded.value().displayName, path.string());

        // No silent fallback to the embedded copy.
        auto missing = loader.load("tess_test.frag");
        ASSERT_FALSE(missing);
        EXPECT_TRUE(contains(missing.error().message, "tess_test.frag")) << missing.error().message;
        EXPECT_TRUE(contains(missing.error().message, "TERRAIN_SHADER_DIR"))
            << missing.error().message;
    }
    ScopedEnv empty("TERRAIN_SHADER_DIR", "");
    EXPECT_FALSE(runtime::ShaderLoader::fromEnvironment().directory().has_value());
}

TEST(ShaderLoader, NamesMustStayInsideTheFolder) {
    const runtime::ShaderLoader loader(kShaderFolder);
    EXPECT_FALSE(loader.load("../CMakeLists.txt"));
    EXPECT_FALSE(loader.load("/etc/passwd"));
    EXPECT_FALSE(loader.load(""));
    EXPECT_TRUE(loader.load("Bindings.h"));
}

}  // namespace
}  // namespace terrain::test
