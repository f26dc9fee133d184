// writeTextAtomically, the one text writer of the manifest, the imagery layers' layer.json
// and camera paths: the file holds exactly the text and no temporary is left; a folder it
// cannot write in is an error naming the file, with nothing half-written left behind and
// an existing file untouched.
#include "TempFolder.h"
#include "terrain/base/AtomicFile.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace terrain {
namespace {

namespace fs = std::filesystem;
using namespace std::string_literals;

std::vector<std::string> entries(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(folder))
        names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::string contents(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

TEST(AtomicTextFileTest, WritesTheTextAndLeavesNoTemporary) {
    const test::TempFolder folder;
    const fs::path path = folder.path() / "layer.json";
    const std::string text = "{\n \"format\": \"x\"\n}\n\0after a NUL"s;
    ASSERT_TRUE(writeTextAtomically(path, text).ok());
    EXPECT_EQ(contents(path), text);
    EXPECT_EQ(entries(folder.path()), std::vector<std::string>{"layer.json"});

    // A second write replaces the file whole.
    ASSERT_TRUE(writeTextAtomically(path, "short\n").ok());
    EXPECT_EQ(contents(path), "short\n");
    EXPECT_EQ(entries(folder.path()), std::vector<std::string>{"layer.json"});
}

TEST(AtomicTextFileTest, AFolderItCannotWriteInIsAnErrorNamingTheFile) {
    const test::TempFolder folder;
    // No such folder.
    const fs::path missing = folder.path() / "missing" / "manifest.json";
    const Status noFolder = writeTextAtomically(missing, "text");
    ASSERT_FALSE(noFolder.ok());
    EXPECT_NE(noFolder.error().message.find(missing.string()), std::string::npos)
        << noFolder.error().message;
    // A plain file where the folder should be.
    std::ofstream(folder.path() / "plain") << "x";
    const fs::path underFile = folder.path() / "plain" / "manifest.json";
    const Status notAFolder = writeTextAtomically(underFile, "text");
    ASSERT_FALSE(notAFolder.ok());
    EXPECT_NE(notAFolder.error().message.find(underFile.string()), std::string::npos)
        << notAFolder.error().message;
    EXPECT_EQ(entries(folder.path()), std::vector<std::string>{"plain"});
    EXPECT_EQ(contents(folder.path() / "plain"), "x");
}

TEST(AtomicTextFileTest, AReadOnlyFolderKeepsItsFileAndGetsNoTemporary) {
    if (::geteuid() == 0) GTEST_SKIP() << "root may write in a read-only folder";
    const test::TempFolder folder;
    const fs::path locked = folder.path() / "locked";
    fs::create_directory(locked);
    const fs::path path = locked / "manifest.json";
    ASSERT_TRUE(writeTextAtomically(path, "old\n").ok());
    ::chmod(locked.c_str(), 0555);
    const Status status = writeTextAtomically(path, "new\n");
    ::chmod(locked.c_str(), 0755);
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find(path.string()), std::string::npos)
        << status.error().message;
    EXPECT_EQ(contents(path), "old\n");
    EXPECT_EQ(entries(locked), std::vector<std::string>{"manifest.json"});
}

}  // namespace
}  // namespace terrain
