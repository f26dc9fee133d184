// Broken DEM inputs: each is an Error whose message starts with the path and says what is
// wrong, never a crash — missing and empty files, truncated files (every reader, many
// prefixes), garbage with a DEM extension, a .hgt of the wrong size, corrupt compressed
// tiles, sample types that are not heights, rotated mosaic inputs.
#include "DemTestSupport.h"
#include "SharedData.h"

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/dem/HeightImageWriter.h"

#include <gdal_priv.h>

#include <array>

namespace terrain::io {
namespace {

using test::openOne;
using test::TempDir;
namespace fs = std::filesystem;

// Opens `path` and reads it whole in bands; the first Error met, or nullopt.
std::optional<std::string> firstError(const std::string& path) {
    Result<std::unique_ptr<DemReader>> reader = openOne(path);
    if (!reader.ok()) return reader.error().message;
    DemReader& r = *reader.value();
    const DemInfo& info = r.info();
    std::vector<float> band(static_cast<std::size_t>(info.width * 131));
    for (std::int64_t y = 0; y < info.height; y += 131) {
        const std::int64_t rows = std::min<std::int64_t>(131, info.height - y);
        const Status s = r.readWindow(0, y, info.width, rows, band);
        if (!s.ok()) return s.error().message;
    }
    return std::nullopt;
}

void expectErrorStartingWithPath(const std::string& path, const std::string& mentions = {}) {
    const std::optional<std::string> error = firstError(path);
    ASSERT_TRUE(error.has_value()) << path << " opened and read without an error";
    EXPECT_TRUE(error->starts_with(path + ":")) << *error;
    if (!mentions.empty()) {
        EXPECT_NE(error->find(mentions), std::string::npos) << *error;
    }
}

class DemReaderErrorsTest : public ::testing::Test {
protected:
    void SetUp() override { GDALAllRegister(); }

    std::string writeGdal(const std::string& name, GDALDataType type,
                          std::vector<std::string> creationOptions = {},
                          std::array<double, 6> gt = {0.0, 1.0, 0.0, 0.0, 0.0, -1.0}) {
        const std::string path = m_dir.file(name);
        GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
        std::vector<char*> options;
        for (std::string& o : creationOptions) options.push_back(o.data());
        options.push_back(nullptr);
        GDALDataset* ds = driver->Create(path.c_str(), 64, 48, 1, type, options.data());
        EXPECT_NE(ds, nullptr);
        if (ds == nullptr) return path;
        ds->SetGeoTransform(gt.data());
        std::vector<float> values(64 * 48, 1.0F);
        EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 64, 48, values.data(), 64, 48,
                                                 GDT_Float32, 0, 0, nullptr),
                  CE_None);
        GDALClose(ds);
        return path;
    }

    TempDir m_dir;
};

TEST_F(DemReaderErrorsTest, MissingFiles) {
    for (const char* name :
         {"missing.tif", "missing.hgt", "missing.nc", "missing.png", "N10E010.hgt"}) {
        const std::string path = m_dir.file(name);
        expectErrorStartingWithPath(path, "no such file");
    }
    // A folder stands for its DEM files (DemInputList.h); this one has none.
    expectErrorStartingWithPath(m_dir.path().string(), "a folder without DEM files");
    const auto none = openDem({});
    EXPECT_FALSE(none.ok());
}

TEST_F(DemReaderErrorsTest, EmptyFiles) {
    for (const char* name : {"empty.tif", "empty.hgt", "empty.nc", "empty.png", "empty.exr",
                             "empty.jpg", "empty.vrt"}) {
        const std::string path = m_dir.file(name);
        test::writeBytes(path, {});
        expectErrorStartingWithPath(path, "empty file");
    }
}

TEST_F(DemReaderErrorsTest, GarbageWithADemExtension) {
    std::vector<char> garbage(100000);
    for (std::size_t i = 0; i < garbage.size(); ++i)
        garbage[i] = static_cast<char>((i * 2654435761U) >> 13U);
    for (const char* name : {"garbage.tif", "garbage.tiff", "garbage.png", "garbage.exr",
                             "garbage.jpg", "garbage.nc", "garbage.dem", "garbage.vrt"}) {
        const std::string path = m_dir.file(name);
        test::writeBytes(path, garbage);
        expectErrorStartingWithPath(path);
    }
    // A netCDF classic header that declares an attribute longer than the file: refused
    // before libnetcdf allocates what it declares (3.6 GB; found by fuzz-dem-netcdf).
    const std::string netCdf = m_dir.file("attribute-longer-than-the-file.nc");
    test::writeBytes(netCdf, test::readBytes(fs::path(TERRAIN_SOURCE_DIR) / "tests" / "fuzz" /
                                             "dem-netcdf" / "attribute-longer-than-the-file.nc"));
    expectErrorStartingWithPath(netCdf, "corrupt netCDF header");
    // A 46 × 12 TIFF whose tiles claim 8448 × 46336 samples: refused before OpenImageIO
    // allocates and clears one (1.5 GB; found by fuzz-dem-tiff).
    const std::string bigTiles = m_dir.file("tiles-8448x46336-for-46x12.tif");
    test::writeBytes(bigTiles, test::readBytes(fs::path(TERRAIN_SOURCE_DIR) / "tests" / "fuzz" /
                                               "dem-tiff" / "tiles-8448x46336-for-46x12.tif"));
    expectErrorStartingWithPath(bigTiles, "tiles of 8448 × 46336 for a 46 × 12 image");
    // A 300-byte file GDAL takes for an NGS geoid grid of 1,283,027,553 × 1,819,044,195
    // samples: refused before GDAL allocates one 5.1 GB line (found by fuzz-dem-asc).
    const std::string geoid = m_dir.file("ngs-geoid-header-claiming-1283027553-columns.asc");
    test::writeBytes(geoid,
                     test::readBytes(fs::path(TERRAIN_SOURCE_DIR) / "tests" / "fuzz" / "dem-asc" /
                                     "ngs-geoid-header-claiming-1283027553-columns.asc"));
    expectErrorStartingWithPath(geoid, "a block decodes to 4894 MiB");
    // A 16 × 12 TIFF claiming 16,129 pixel-interleaved float32 bands in 256 × 256 tiles:
    // refused before GDAL allocates one tile of every band to read the first (4.2 GB; found
    // by fuzz-dem-tiff).
    const std::string interleaved = m_dir.file("16129-interleaved-bands-in-256x256-tiles.tif");
    test::writeBytes(interleaved,
                     test::readBytes(fs::path(TERRAIN_SOURCE_DIR) / "tests" / "fuzz" / "dem-tiff" /
                                     "16129-interleaved-bands-in-256x256-tiles.tif"));
    expectErrorStartingWithPath(interleaved,
                                "of 16129 interleaved bands in blocks of 256 × 256: a block "
                                "decodes to 4032 MiB");
    // A TIFF header and nothing else.
    const std::string header = m_dir.file("header_only.tif");
    test::writeBytes(header, {'I', 'I', 42, 0, 8, 0, 0, 0});
    expectErrorStartingWithPath(header);
}

TEST_F(DemReaderErrorsTest, DecodeLimitIsAnOpenOption) {
    // The fuzz targets lower DemOpenOptions::maxDecodeBytes so that inputs near the 2 GiB
    // default cost milliseconds; both readers must take it. A 4096-column float32 TIFF
    // decodes 256 rows (or a row of 256-row tiles) at once, 4 MiB, which a 1 MiB limit
    // refuses and the default reads.
    const std::string tiff = m_dir.file("4096-columns.tif");
    const std::vector<float> heights(4096 * 2, 100.0F);
    ASSERT_TRUE(writeHeightImage(tiff, 4096, 2, heights).ok());
    DemOpenOptions oneMiB;
    oneMiB.maxDecodeBytes = std::uint64_t{1} << 20U;
    const Result<std::unique_ptr<DemReader>> refused = openOne(tiff, oneMiB);
    ASSERT_FALSE(refused.ok()) << tiff << " opened under a 1 MiB decode limit";
    EXPECT_TRUE(refused.error().message.starts_with(tiff + ":")) << refused.error().message;
    EXPECT_NE(refused.error().message.find("decodes to 4 MiB, more than the 1 MiB"),
              std::string::npos)
        << refused.error().message;
    EXPECT_FALSE(firstError(tiff).has_value()) << *firstError(tiff);

    // GDAL's blocks: an ASCII grid's block is one row, 600,000 int32 samples (2.3 MiB); the
    // file holds the first (GDAL opens no grid without a value).
    const std::string grid = m_dir.file("600000-columns.asc");
    const std::string header =
        "ncols 600000\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 30\n1\n";
    test::writeBytes(grid, std::vector<char>(header.begin(), header.end()));
    const Result<std::unique_ptr<DemReader>> refusedGrid = openOne(grid, oneMiB);
    ASSERT_FALSE(refusedGrid.ok()) << grid << " opened under a 1 MiB decode limit";
    EXPECT_TRUE(refusedGrid.error().message.starts_with(grid + ":")) << refusedGrid.error().message;
    EXPECT_NE(refusedGrid.error().message.find("a block decodes to 2 MiB, more than the 1 MiB"),
              std::string::npos)
        << refusedGrid.error().message;
    // Under the default the header passes the limit; the missing row is the error.
    const Result<std::unique_ptr<DemReader>> underDefault = openOne(grid);
    ASSERT_FALSE(underDefault.ok()) << grid << " opened without its samples";
    EXPECT_EQ(underDefault.error().message.find("a block decodes to"), std::string::npos)
        << underDefault.error().message;
}

TEST_F(DemReaderErrorsTest, AsciiGridThatBreaksOffIsRefusedAtOpen) {
    // GDAL's ASCII grid driver finds a line by reading the unknown lines before it,
    // recursively: in a file that ends early, reading the last of 40 rows first took 2^40
    // reads (a 210-byte fuzz input with 61 rows spun for minutes; tests/fuzz/dem-asc/). The
    // reader reads the rows in order at open instead, so such a file is an error there.
    const auto grid = [](int promisedRows, int writtenRows) {
        std::string text = "ncols 4\nnrows " + std::to_string(promisedRows) +
                           "\nxllcorner 0\nyllcorner 0\ncellsize 30\n";
        for (int y = 0; y < writtenRows; ++y)
            text += std::to_string(10 * y) + " " + std::to_string(10 * y + 1) + " " +
                    std::to_string(10 * y + 2) + " " + std::to_string(10 * y + 3) + "\n";
        return std::vector<char>(text.begin(), text.end());
    };
    const std::string broken = m_dir.file("breaks-off.asc");
    test::writeBytes(broken, grid(40, 3));
    const Result<std::unique_ptr<DemReader>> refused = openOne(broken);
    ASSERT_FALSE(refused.ok()) << broken << " opened";
    EXPECT_TRUE(refused.error().message.starts_with(broken + ":")) << refused.error().message;
    EXPECT_NE(refused.error().message.find("row 3 of the 40"), std::string::npos)
        << refused.error().message;

    // A whole one opens and reads, its last rows first.
    const std::string whole = m_dir.file("whole.asc");
    test::writeBytes(whole, grid(40, 40));
    Result<std::unique_ptr<DemReader>> opened = openOne(whole);
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    ASSERT_EQ(opened.value()->info().height, 40);
    std::vector<float> last(4 * 2);
    ASSERT_TRUE(opened.value()->readWindow(0, 38, 4, 2, last).ok());
    EXPECT_EQ(last, (std::vector<float>{380, 381, 382, 383, 390, 391, 392, 393}));
}

TEST_F(DemReaderErrorsTest, HgtOfTheWrongSize) {
    const std::string path = m_dir.file("N46W122.hgt");
    test::writeBytes(path, std::vector<char>(1000, 0));
    expectErrorStartingWithPath(path, "1000 bytes");
    const std::string almost = m_dir.file("N46W121.hgt");
    test::writeBytes(almost, std::vector<char>(1201 * 1201 * 2 - 2, 0));
    expectErrorStartingWithPath(almost, "not an SRTM .hgt size");
}

TEST_F(DemReaderErrorsTest, TruncatedRainierTiff) {
    TERRAIN_SHARED_DATA_OR_SKIP(path, "srtm3_n46w122_rainier.tif");
    std::vector<char> bytes = test::readBytes(path);
    bytes.resize(bytes.size() / 2);
    const std::string truncated = m_dir.file("dem.tif");
    test::writeBytes(truncated, bytes);
    // This file keeps its directory at the end: the header points past the cut.
    expectErrorStartingWithPath(truncated, "truncated: the TIFF directory");
    // Our writer's files too; a GDAL file with the directory first loses tiles instead.
    GDALDataset* source = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
    ASSERT_NE(source, nullptr);
    const std::string copy = m_dir.file("directory_first.tif");
    char tiled[] = "TILED=YES";
    char* options[] = {tiled, nullptr};
    GDALClose(GetGDALDriverManager()->GetDriverByName("GTiff")->CreateCopy(
        copy.c_str(), source, FALSE, options, nullptr, nullptr));
    GDALClose(source);
    bytes = test::readBytes(copy);
    bytes.resize(bytes.size() / 2);
    test::writeBytes(truncated, bytes);
    expectErrorStartingWithPath(truncated, "truncated: TIFF tile");
}

TEST_F(DemReaderErrorsTest, EveryReaderSurvivesTruncatedPrefixes) {
    // meshoptimizer-style, on evenly spaced prefixes (8 to 400 a file, the empty one
    // included) of every real DEM: each must fail cleanly with an error naming the file,
    // never crash nor read as if whole (netCDF classic and JPEG decoders would fill the cut
    // part: the readers check the header's extent and the JPEG end marker).
    struct Case {
        const char* name;
        int prefixes;
    };
    for (const Case c : {Case{"luxembourg_elev_30s.tif", 400},
                         Case{"srtm3_n46w122_rainier.tif", 40}, Case{"srtm/N57E011.hgt", 10},
                         Case{"kilauea_utm5n_30m.nc", 30}, Case{"etopo20_global.nc", 40},
                         Case{"puget_sound_1k.png", 12}, Case{"puget_sound_4k_8bit.jpg", 8}}) {
        TERRAIN_SHARED_DATA_OR_SKIP(path, c.name);
        const std::vector<char> bytes = test::readBytes(path);
        const std::string ext = path.extension().string();
        const std::string prefix = m_dir.file(std::string("N57E011") + ext);
        std::size_t failures = 0;
        for (int i = 0; i < c.prefixes; ++i) {
            const std::size_t length =
                bytes.size() * static_cast<std::size_t>(i) / static_cast<std::size_t>(c.prefixes);
            test::writeBytes(prefix, std::vector<char>(bytes.begin(), bytes.begin() + length));
            const std::optional<std::string> error = firstError(prefix);
            if (!error) {
                ADD_FAILURE() << c.name << " prefix of " << length << " bytes read";
                continue;
            }
            ++failures;
            EXPECT_TRUE(error->starts_with(prefix + ":")) << *error;
        }
        EXPECT_EQ(failures, static_cast<std::size_t>(c.prefixes)) << c.name;
    }
}

TEST_F(DemReaderErrorsTest, CorruptCompressedTile) {
    std::vector<float> heights(600 * 300);
    for (std::size_t i = 0; i < heights.size(); ++i) heights[i] = static_cast<float>(i % 977);
    const std::string path = m_dir.file("corrupt.tif");
    ASSERT_TRUE(writeHeightImage(path, 600, 300, heights).ok());
    std::vector<char> bytes = test::readBytes(path);
    // libtiff writes tiles first, the directory last: scribble over the first tiles.
    for (std::size_t i = 16; i < bytes.size() / 2; ++i) bytes[i] = static_cast<char>(i * 7919U);
    test::writeBytes(path, bytes);
    expectErrorStartingWithPath(path, "cannot read rows");
}

TEST_F(DemReaderErrorsTest, CorruptPngData) {
    std::vector<float> heights(400 * 300);
    for (std::size_t i = 0; i < heights.size(); ++i) heights[i] = static_cast<float>(i % 1009);
    const std::string path = m_dir.file("corrupt.png");
    ASSERT_TRUE(writeHeightImage(path, 400, 300, heights).ok());
    std::vector<char> bytes = test::readBytes(path);
    // Keep the chunk structure, scramble the compressed pixels of the first IDAT chunk.
    const std::string_view all(bytes.data(), bytes.size());
    const std::size_t idat = all.find("IDAT");
    ASSERT_NE(idat, std::string_view::npos);
    for (std::size_t i = idat + 40; i < std::min(bytes.size() - 16, idat + 4000); ++i)
        bytes[i] = static_cast<char>(i * 131U);
    test::writeBytes(path, bytes);
    expectErrorStartingWithPath(path);
}

TEST_F(DemReaderErrorsTest, UnsupportedSampleTypes) {
    const std::string complexTif = writeGdal("complex.tif", GDT_CInt16);
    expectErrorStartingWithPath(complexTif, "complex");
    // The same bytes under a name GDAL gets.
    const std::string complexGdal = m_dir.file("complex.gtiff_raster");
    fs::copy_file(complexTif, complexGdal);
    expectErrorStartingWithPath(complexGdal, "CInt16");

    const std::string oneBit = writeGdal("one_bit.tif", GDT_Byte, {"NBITS=1"});
    expectErrorStartingWithPath(oneBit, "1-bit");
    const std::string twelveBit = writeGdal("twelve_bit.tif", GDT_UInt16, {"NBITS=12"});
    expectErrorStartingWithPath(twelveBit, "12-bit");
}

// One rotated raster is resampled (GdalInputsTest); a degenerate placement cannot be, and
// a mosaic's inputs must share one north-up grid.
TEST_F(DemReaderErrorsTest, RotatedRasters) {
    const std::array<double, 6> flat = {100.0, 1.0, 1.0, 200.0, 1.0, 1.0};  // no area
    const std::string degenerate = writeGdal("degenerate.tif", GDT_Float32, {}, flat);
    expectErrorStartingWithPath(degenerate, "geotransform");
    const std::array<double, 6> rotated = {100.0, 1.0, 0.2, 200.0, 0.2, -1.0};
    const std::string tif = writeGdal("rotated.tif", GDT_Float32, {}, rotated);
    const std::string other = m_dir.file("rotated.gtiff_raster");
    fs::copy_file(tif, other);
    const auto mosaic = openDem({tif, other});
    ASSERT_FALSE(mosaic.ok());
    EXPECT_TRUE(mosaic.error().message.starts_with(tif + ":")) << mosaic.error().message;
    EXPECT_NE(mosaic.error().message.find("rotated"), std::string::npos) << mosaic.error().message;
}

TEST_F(DemReaderErrorsTest, MessagesAreReadable) {
    // Spot-check full texts, so a change of wording is a deliberate one.
    const std::string path = m_dir.file("N46W122.hgt");
    test::writeBytes(path, std::vector<char>(1000, 0));
    EXPECT_EQ(firstError(path).value_or(""),
              path +
                  ": 1000 bytes is not an SRTM .hgt size (2884802 bytes for 1201² samples, "
                  "25934402 for 3601²)");
    EXPECT_EQ(firstError(m_dir.file("gone.tif")).value_or(""),
              m_dir.file("gone.tif") + ": no such file");
}

}  // namespace
}  // namespace terrain::io
