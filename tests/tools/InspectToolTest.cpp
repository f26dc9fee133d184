// terrain-inspect as a user runs it, on tiny pyramids the test writes itself (shards and a
// manifest, no builder): the exit status, the problems it names, its JSON summary.
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/pyramid/ShardWriter.h"

#include "TinyPyramid.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;

struct ToolRun {
    int status = -1;
    std::string output;  // stdout and stderr together
    std::string stdoutOnly;
};

ToolRun inspect(const std::string& arguments) {
    ToolRun run;
    const fs::path errFile =
        fs::temp_directory_path() / ("terrain-inspect-test-" + std::to_string(::getpid()) + ".err");
    const std::string command =
        std::string(TERRAIN_INSPECT) + " " + arguments + " 2>" + errFile.string();
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) return run;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.stdoutOnly.append(buffer, n);
    const int status = ::pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream err(errFile);
    run.output = run.stdoutOnly + std::string(std::istreambuf_iterator<char>(err), {});
    fs::remove(errFile);
    return run;
}

bool contains(const std::string& text, const std::string& needle) {
    return text.find(needle) != std::string::npos;
}

class InspectTool : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() /
                ("terrain-inspect-" + std::to_string(::getpid()) + "-" + test->name());
        fs::remove_all(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    test::TinyPyramidOptions options() const {
        test::TinyPyramidOptions o;
        o.withNoData = true;
        o.absent = [](const PatchId& id) { return id.level == 3 && id.x == 4 && id.y == 3; };
        return o;
    }

    // Rewrites the shard holding `id` with `edit` applied to that patch's record.
    void rewritePatch(const PatchId& id, const std::function<void(PatchRecord&)>& edit) {
        const test::TinyPyramidOptions o = options();
        const PyramidLayout layout =
            PyramidLayout::create(o.width, o.height, o.patchSamples, o.blockQuads, o.shardPatches)
                .value();
        test::TinyPyramid tiny(layout, o);
        const ShardId s = layout.shardOf(id);
        auto writer = ShardWriter::create(m_dir / layout.shardPath(s), layout, s, o.withNoData);
        ASSERT_TRUE(writer.ok());
        for (int ty = 0; ty < layout.shardCountY(s); ++ty)
            for (int tx = 0; tx < layout.shardCountX(s); ++tx) {
                const PatchId p{s.level, layout.shardFirstX(s) + tx, layout.shardFirstY(s) + ty};
                if (tiny.isAbsent(p)) continue;
                PatchRecord r = tiny.patch(p);
                if (p == id) edit(r);
                ASSERT_TRUE(writer.value().writePatch(r).ok());
            }
        ASSERT_TRUE(writer.value().finish().ok());
    }

    fs::path m_dir;
};

TEST_F(InspectTool, Help) {
    const ToolRun run = inspect("--help");
    EXPECT_EQ(run.status, 0);
    EXPECT_TRUE(contains(run.output, "--verify")) << run.output;
    EXPECT_TRUE(contains(run.output, "--json")) << run.output;
}

TEST_F(InspectTool, MissingFolderFailsNamingIt) {
    const ToolRun run = inspect((m_dir / "no-such-pyramid").string());
    EXPECT_EQ(run.status, 1);
    EXPECT_TRUE(contains(run.output, (m_dir / "no-such-pyramid").string() + ": not a pyramid"))
        << run.output;
}

TEST_F(InspectTool, FolderWithoutManifestIsNotAPyramid) {
    fs::create_directories(m_dir);
    const ToolRun run = inspect(m_dir.string());
    EXPECT_EQ(run.status, 1);
    EXPECT_TRUE(contains(run.output, m_dir.string() + ": not a pyramid: no manifest.json"))
        << run.output;
}

TEST_F(InspectTool, GoodPyramidVerifies) {
    ASSERT_TRUE(test::writeTinyPyramid(m_dir, options()).ok());
    ToolRun run = inspect(m_dir.string() + " --verify");
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(contains(run.output, "no problems found")) << run.output;
    EXPECT_TRUE(contains(run.output, "37 × 29 samples")) << run.output;

    run = inspect(m_dir.string() + " --verify --json");
    ASSERT_EQ(run.status, 0) << run.output;
    const auto json = nlohmann::json::parse(run.stdoutOnly);
    EXPECT_EQ(json["ok"], true);
    EXPECT_EQ(json["manifest"]["formatVersion"], 8);
    ASSERT_EQ(json["levels"].size(), 4U);
    EXPECT_EQ(json["levels"][3]["presentPatches"], 19);
    EXPECT_EQ(json["levels"][0]["presentPatches"], 1);
    EXPECT_GT(json["levels"][3]["bytes"].get<std::int64_t>(), 0);
    EXPECT_EQ(json["verify"]["patchesChecked"], 19 + 6 + 2 + 1);  // 5×4−1, 3×2, 2×1, 1
    EXPECT_GE(json["levels"][0]["error"]["max"].get<double>(),
              json["levels"][1]["error"]["max"].get<double>());

    run = inspect(m_dir.string() + " --json");  // no --verify: nothing read but the infos
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(nlohmann::json::parse(run.stdoutOnly)["verify"].is_null());
}

TEST_F(InspectTool, CorruptShardIsReportedWithItsFile) {
    ASSERT_TRUE(test::writeTinyPyramid(m_dir, options()).ok());
    const fs::path shard = m_dir / "L3" / "0" / "1.exr";
    std::vector<char> bytes;
    {
        std::ifstream in(shard, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x01);
    {
        std::ofstream out(shard, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    const ToolRun run = inspect(m_dir.string() + " --verify");
    EXPECT_EQ(run.status, 1) << run.output;
    EXPECT_TRUE(contains(run.output, "problem: " + shard.string() + ": patch L3")) << run.output;
    EXPECT_TRUE(contains(run.output, "problems found")) << run.output;
}

TEST_F(InspectTool, MissingShardIsAProblem) {
    ASSERT_TRUE(test::writeTinyPyramid(m_dir, options()).ok());
    fs::remove(m_dir / "L2" / "0" / "0.exr");
    const ToolRun run = inspect(m_dir.string());
    EXPECT_EQ(run.status, 1);
    EXPECT_TRUE(contains(run.output, (m_dir / "L2/0/0.exr").string() + ": patch L2 (0, 0): the "
                                                                       "shard file is missing"))
        << run.output;
}

TEST_F(InspectTool, WrongBlockErrorsAndBrokenNestingAreProblems) {
    ASSERT_TRUE(test::writeTinyPyramid(m_dir, options()).ok());
    rewritePatch({3, 1, 1}, [](PatchRecord& r) { r.blockErrors[1][2] += 0.5f; });
    rewritePatch({1, 0, 0}, [](PatchRecord& r) {
        r.info.approxError = 0.0f;  // below its children's: the bounds no longer nest
        r.info.error = 0.0f;
    });
    rewritePatch({2, 2, 1}, [](PatchRecord& r) { r.info.minHeight -= 1.0f; });
    const ToolRun run = inspect(m_dir.string() + " --verify --json");
    EXPECT_EQ(run.status, 1);
    const auto json = nlohmann::json::parse(run.stdoutOnly);
    EXPECT_EQ(json["ok"], false);
    std::string all;
    for (const auto& p : json["problems"]) all += p["message"].get<std::string>() + "\n";
    EXPECT_TRUE(contains(all, "L3/0/0.exr: patch L3 (1, 1): block (1, 0): stored λ(1..4)")) << all;
    EXPECT_TRUE(contains(all, "L1/0/0.exr: patch L1 (0, 0): Err_Appr 0 m is below its child L2"))
        << all;
    EXPECT_TRUE(contains(all, "L2/0/1.exr: patch L2 (2, 1): stored min/max")) << all;
}

}  // namespace
}  // namespace terrain::io
