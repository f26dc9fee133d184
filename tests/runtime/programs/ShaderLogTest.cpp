// translateShaderLog: driver log lines in Mesa, NVIDIA and AMD formats become
// "<file>:<line>: ..."; the file comes from the line number (file n is numbered from
// n * 100000 + 1), not from the source-string number drivers report.
#include "terrain/runtime/ShaderLog.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace terrain::test {
namespace {

const std::vector<std::string> kSources = {"terrain.tese", "Bindings.h", "Common.glsl"};

TEST(ShaderLog, MesaFormatKeepsColumn) {
    EXPECT_EQ(runtime::translateShaderLog("0:12(5): error: `foo' undeclared\n", kSources),
              "terrain.tese:12:5: error: `foo' undeclared");
    EXPECT_EQ(runtime::translateShaderLog("2:200003(14): warning: unused\n", kSources),
              "Common.glsl:3:14: warning: unused");
}

TEST(ShaderLog, MesaSourceZeroForIncludedLinesStillNamesTheIncludedFile) {
    // Mesa reports source 0 for errors found after parsing, even inside an include.
    EXPECT_EQ(runtime::translateShaderLog("0:100003(9): error: `x' undeclared", kSources),
              "Bindings.h:3:9: error: `x' undeclared");
}

TEST(ShaderLog, NvidiaFormat) {
    EXPECT_EQ(
        runtime::translateShaderLog("1(100007) : error C1008: undefined variable \"x\"", kSources),
        "Bindings.h:7: error C1008: undefined variable \"x\"");
}

TEST(ShaderLog, AmdFormatMovesSeverityAfterLocation) {
    EXPECT_EQ(runtime::translateShaderLog("ERROR: 0:40: 'x' : undeclared identifier", kSources),
              "terrain.tese:40: error: 'x' : undeclared identifier");
    EXPECT_EQ(runtime::translateShaderLog("WARNING: 2:200001: something", kSources),
              "Common.glsl:1: warning: something");
}

TEST(ShaderLog, SeveralLinesAndUnknownLinesPassThrough) {
    const std::string log =
        "0:1(1): error: first\r\n"
        "note: no location here\n"
        "\n"
        "7:700002(3): error: unknown source\n";
    EXPECT_EQ(runtime::translateShaderLog(log, kSources),
              "terrain.tese:1:1: error: first\n"
              "note: no location here\n"
              "<source 7>:2:3: error: unknown source");
}

TEST(ShaderLog, NotQuiteLocationsAreLeftAlone) {
    EXPECT_EQ(runtime::translateShaderLog("0:12 error without column", kSources),
              "0:12 error without column");
    EXPECT_EQ(runtime::translateShaderLog("ERROR: 0 errors", kSources), "ERROR: 0 errors");
}

}  // namespace
}  // namespace terrain::test
