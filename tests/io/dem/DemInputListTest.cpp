// A folder of SRTM tiles and a file pattern as DEM inputs (openDem, DemInputList.h), with
// .hgt tiles written here by the .hgt writer: the folder, the pattern and the list of its
// files open as the same mosaic, sample for sample; a folder without DEM files and a pattern
// matching nothing are Errors naming them; the writer keeps SRTM's sizes and voids.
#include "DemTestSupport.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/dem/HeightImageWriter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace terrain::io {
namespace {

using test::readAll;
using test::TempDir;

// Tile (column, row) of a 2 × 2 set south-west at 46° N, 122° W: heights a function of the
// whole set's sample, so shared edges agree.
float setHeight(std::int64_t x, std::int64_t y) {
    return static_cast<float>(std::lround(500.0 + 300.0 * std::sin(double(x) * 0.01) +
                                          200.0 * std::cos(double(y) * 0.013)));
}

void writeTile(const std::filesystem::path& folder, const std::string& name, int column, int row) {
    auto written =
        writeHeightImage(folder / name, 1201, 1201,
                         [&](std::int64_t firstRow, std::int64_t rows, std::span<float> out) {
                             for (std::int64_t r = 0; r < rows; ++r)
                                 for (std::int64_t c = 0; c < 1201; ++c)
                                     out[static_cast<std::size_t>(r * 1201 + c)] =
                                         setHeight(column * 1200 + c, row * 1200 + firstRow + r);
                         });
    ASSERT_TRUE(written.ok()) << written.error().message;
}

class DemInputListTest : public ::testing::Test {
protected:
    void SetUp() override {
        std::filesystem::create_directories(m_tiles);
        writeTile(m_tiles, "N47W122.hgt", 0, 0);
        writeTile(m_tiles, "N47W121.hgt", 1, 0);
        writeTile(m_tiles, "N46W122.hgt", 0, 1);
        writeTile(m_tiles, "N46W121.hgt", 1, 1);
        std::ofstream(m_tiles / "README.txt") << "not a DEM\n";
    }

    std::unique_ptr<DemReader> mustOpen(const std::vector<std::string>& inputs) {
        auto reader = openDem(inputs);
        EXPECT_TRUE(reader.ok()) << reader.error().message;
        return reader.ok() ? std::move(reader).value() : nullptr;
    }

    TempDir m_dir;
    std::filesystem::path m_tiles = m_dir.path() / "tiles";
};

TEST_F(DemInputListTest, AFolderAndAPatternOpenAsTheMosaicOfTheirFiles) {
    const std::string folder = m_tiles.string();
    auto listed = mustOpen({folder + "/N46W121.hgt", folder + "/N46W122.hgt",
                            folder + "/N47W121.hgt", folder + "/N47W122.hgt"});
    auto fromFolder = mustOpen({folder});
    auto fromPattern = mustOpen({folder + "/N4?W12*.hgt"});
    ASSERT_TRUE(listed && fromFolder && fromPattern);
    EXPECT_EQ(fromFolder->info().width, 2401);
    EXPECT_EQ(fromFolder->info().height, 2401);
    EXPECT_EQ(fromFolder->info().inputs, listed->info().inputs);
    EXPECT_EQ(fromPattern->info().inputs, listed->info().inputs);
    const std::vector<float> all = readAll(*fromFolder);
    EXPECT_EQ(all, readAll(*fromPattern));
    // North-west sample of the set, and one of the south-east tile.
    EXPECT_EQ(all[0], setHeight(0, 0));
    EXPECT_EQ(all[2000 * 2401 + 1900], setHeight(1900, 2000));
}

TEST_F(DemInputListTest, AFolderWithoutDemsAndAPatternMatchingNothingAreErrors) {
    const auto empty = m_dir.path() / "empty";
    std::filesystem::create_directories(empty);
    std::ofstream(empty / "notes.txt") << "no DEM here\n";
    auto folder = openDem({empty.string()});
    ASSERT_FALSE(folder.ok());
    EXPECT_NE(folder.error().message.find(empty.string() + ": a folder without DEM files"),
              std::string::npos)
        << folder.error().message;
    const std::string pattern = (m_tiles / "S*.hgt").string();
    auto none = openDem({pattern});
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().message, pattern + ": matches no file");
}

TEST_F(DemInputListTest, TheHgtWriterKeepsSrtmSizesAndVoids) {
    const auto path = m_dir.path() / "N10E010.hgt";
    auto wrong = writeHeightImage(path, 1000, 1000, std::vector<float>(1000 * 1000, 1.0f));
    ASSERT_FALSE(wrong.ok());
    EXPECT_NE(wrong.error().message.find("1201 × 1201"), std::string::npos);
    std::vector<float> heights(1201 * 1201, 12.4f);
    heights[5] = std::numeric_limits<float>::quiet_NaN();  // a void
    heights[6] = 40000.0f;                                 // beyond int16: clamped
    heights[7] = -7.6f;
    ASSERT_TRUE(writeHeightImage(path, 1201, 1201, heights).ok());
    auto reader = mustOpen({path.string()});
    ASSERT_TRUE(reader);
    const std::vector<float> back = readAll(*reader);
    EXPECT_EQ(back[0], 12.0f);
    EXPECT_TRUE(std::isnan(back[5]));
    EXPECT_EQ(back[6], 32767.0f);
    EXPECT_EQ(back[7], -8.0f);
}

}  // namespace
}  // namespace terrain::io
