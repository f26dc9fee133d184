// Fuzz target: a DEM file as the builder opens it (io::openDem, then windows read as the
// builder reads them). One source, compiled once per format: TERRAIN_FUZZ_DEM_FILE names
// the file the input is written to, and its extension picks the reader as openDem does
// (.tif: OpenImageIO plus our GeoTIFF georeference and no-data tag reading; .png and
// .exr: OpenImageIO; .hgt: our SRTM reader, which also reads the tile's corner from the
// name; .nc: GDAL plus our netCDF classic extent check; .asc: GDAL's ASCII grid driver, a
// fast text format through the same GDAL boundary of ours: georeference, no-data, sizes,
// windows). A file openDem accepts must read:
// every window is either its samples or an Error, never a crash or a hang; a projected one
// is opened again as a globe build opens it (onto a longitude/latitude grid) and read too.
#include "FuzzScratch.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"
#include "terrain/dem/HeightImageWriter.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#ifndef TERRAIN_FUZZ_DEM_FILE
#error "TERRAIN_FUZZ_DEM_FILE names the input file, e.g. \"input.tif\""
#endif

namespace {

namespace fs = terrain::fuzz::fs;
constexpr std::string_view kInputFile = TERRAIN_FUZZ_DEM_FILE;

// A smooth 16 × 12 test raster, NaN in one corner (no-data where the format has it).
std::vector<float> seedHeights(std::int64_t width, std::int64_t height) {
    std::vector<float> h(static_cast<std::size_t>(width * height));
    for (std::int64_t y = 0; y < height; ++y)
        for (std::int64_t x = 0; x < width; ++x)
            h[static_cast<std::size_t>(y * width + x)] = static_cast<float>(
                120.0 + 30.0 * std::sin(0.4 * double(x)) * std::cos(0.3 * double(y)));
    return h;
}

void writeImageSeeds(const fs::path& seeds, const std::string& extension) {
    using namespace terrain;
    constexpr std::int64_t kWidth = 16, kHeight = 12;
    const std::vector<float> heights = seedHeights(kWidth, kHeight);
    io::HeightImageOptions options;
    if (extension == ".tif") {
        io::Georeference geographic;
        geographic.crsKind = io::CrsKind::Geographic;
        geographic.epsg = io::Georeference::kWgs84Geographic;
        geographic.originX = -122.0;
        geographic.originY = 47.0;
        geographic.pixelSizeX = geographic.pixelSizeY = 1.0 / 1200.0;
        options.georeference = geographic;
        io::Georeference projected;
        projected.epsg = 32610;
        projected.originX = 590000.0;
        projected.originY = 5190000.0;
        projected.pixelSizeX = projected.pixelSizeY = 30.0;
        io::HeightImageOptions utm = options;
        utm.georeference = projected;
        if (auto w = io::writeHeightImage(seeds / "projected.tif", kWidth, kHeight, heights, utm);
            !w)
            fuzz::harnessFailure(w.error().message);
    }
    if (auto w =
            io::writeHeightImage(seeds / ("seed" + extension), kWidth, kHeight, heights, options);
        !w)
        fuzz::harnessFailure(w.error().message);
}

// An SRTM3 tile: 1201² big-endian int16, a few voids (−32768).
void writeHgtSeed(const fs::path& seeds) {
    constexpr std::size_t kSide = 1201;
    std::vector<std::uint8_t> bytes(kSide * kSide * 2, 0);
    for (std::size_t i = 0; i < kSide * kSide; ++i) {
        const auto v = static_cast<std::int16_t>(i % 7 == 0 ? -32768 : (i % 2000));
        bytes[2 * i] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) >> 8);
        bytes[2 * i + 1] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) & 0xFF);
    }
    terrain::fuzz::writeFile(seeds / "N46W122.hgt", bytes);
}

// netCDF classic (CDF-1), written by hand so the seed needs no netCDF library:
// lat(lat), lon(lon) in degrees and z(lat, lon) float with CF units and a fill value.
class CdfWriter {
public:
    void u32(std::uint32_t v) {
        for (int s = 24; s >= 0; s -= 8) m_bytes.push_back(static_cast<std::uint8_t>(v >> s));
    }
    void name(std::string_view n) {
        u32(static_cast<std::uint32_t>(n.size()));
        m_bytes.insert(m_bytes.end(), n.begin(), n.end());
        pad();
    }
    void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
    void f64(double v) {
        const auto bits = std::bit_cast<std::uint64_t>(v);
        u32(static_cast<std::uint32_t>(bits >> 32));
        u32(static_cast<std::uint32_t>(bits));
    }
    void textAttribute(std::string_view key, std::string_view value) {
        name(key);
        u32(2);  // NC_CHAR
        name(value);
    }
    void pad() {
        while (m_bytes.size() % 4 != 0) m_bytes.push_back(0);
    }
    std::size_t size() const { return m_bytes.size(); }
    std::vector<std::uint8_t>& bytes() { return m_bytes; }

private:
    std::vector<std::uint8_t> m_bytes;
};

std::vector<std::uint8_t> netCdfSeed(std::string_view units, float scale) {
    constexpr std::uint32_t kLat = 6, kLon = 8;
    constexpr std::uint32_t kNcDimension = 0x0A, kNcVariable = 0x0B, kNcAttribute = 0x0C;
    constexpr std::uint32_t kFloat = 5, kDouble = 6;
    // The header is written twice: once to learn its size (the data offsets are in it).
    std::uint32_t headerSize = 0;
    for (int pass = 0; pass < 2; ++pass) {
        CdfWriter w;
        w.bytes() = {'C', 'D', 'F', 1};
        w.u32(0);  // numrecs
        w.u32(kNcDimension);
        w.u32(2);
        w.name("lat");
        w.u32(kLat);
        w.name("lon");
        w.u32(kLon);
        w.u32(0);  // no global attributes
        w.u32(0);
        w.u32(kNcVariable);
        w.u32(3);
        std::uint32_t offset = headerSize;
        const auto variable = [&](std::string_view n, std::vector<std::uint32_t> dims,
                                  std::vector<std::pair<std::string_view, std::string_view>> text,
                                  bool fill, std::uint32_t type, std::uint32_t bytes) {
            w.name(n);
            w.u32(static_cast<std::uint32_t>(dims.size()));
            for (std::uint32_t d : dims) w.u32(d);
            const std::uint32_t attributes =
                static_cast<std::uint32_t>(text.size()) + (fill ? 2 : 0);
            if (attributes == 0) {
                w.u32(0);
                w.u32(0);
            } else {
                w.u32(kNcAttribute);
                w.u32(attributes);
                for (auto [key, value] : text) w.textAttribute(key, value);
                if (fill) {
                    w.name("_FillValue");
                    w.u32(kFloat);
                    w.u32(1);
                    w.f32(-9999.0F);
                    w.name("scale_factor");
                    w.u32(kFloat);
                    w.u32(1);
                    w.f32(scale);
                }
            }
            w.u32(type);
            w.u32(bytes);
            w.u32(offset);
            offset += bytes;
        };
        variable("lat", {0}, {{"units", "degrees_north"}}, false, kDouble, kLat * 8);
        variable("lon", {1}, {{"units", "degrees_east"}}, false, kDouble, kLon * 8);
        variable("z", {0, 1}, {{"units", units}}, true, kFloat, kLat * kLon * 4);
        if (pass == 0) {
            headerSize = static_cast<std::uint32_t>(w.size());
            continue;
        }
        for (std::uint32_t i = 0; i < kLat; ++i) w.f64(46.0 + 0.1 * i);
        for (std::uint32_t i = 0; i < kLon; ++i) w.f64(-122.0 + 0.1 * i);
        for (std::uint32_t i = 0; i < kLat * kLon; ++i)
            w.f32(i == 5 ? -9999.0F : 1.2F + 0.01F * static_cast<float>(i));
        return w.bytes();
    }
    return {};
}

// An ASCII grid (Esri / GDAL AAIGrid), 8 × 6, in its two header spellings: corner origin
// with one cell size and no-data, and centre origin with separate dx, dy.
std::string asciiGridSeed(bool centreOrigin) {
    constexpr int kColumns = 8, kRows = 6;
    std::string text =
        "ncols " + std::to_string(kColumns) + "\nnrows " + std::to_string(kRows) + "\n";
    text += centreOrigin
                ? "xllcenter 500015\nyllcenter 5100015\ndx 30\ndy 20\n"
                : "xllcorner -122.5\nyllcorner 46.25\ncellsize 0.001\nNODATA_value -9999\n";
    for (int y = 0; y < kRows; ++y) {
        for (int x = 0; x < kColumns; ++x) {
            const bool noData = !centreOrigin && x == 0 && y == 0;
            text += noData ? "-9999" : std::to_string(100 + 3 * x + 7 * y) + ".5";
            text += x + 1 < kColumns ? " " : "\n";
        }
    }
    return text;
}

void writeSeeds(const fs::path& seeds, const std::string& extension) {
    if (extension == ".hgt") {
        writeHgtSeed(seeds);
    } else if (extension == ".nc") {
        terrain::fuzz::writeFile(seeds / "km.nc", netCdfSeed("km", 1.0F));
        terrain::fuzz::writeFile(seeds / "scaled-m.nc", netCdfSeed("m", 0.5F));
    } else if (extension == ".asc") {
        for (const bool centre : {false, true}) {
            const std::string text = asciiGridSeed(centre);
            const std::vector<std::uint8_t> bytes(text.begin(), text.end());
            terrain::fuzz::writeFile(seeds / (centre ? "centre-dx-dy.asc" : "corner-nodata.asc"),
                                     bytes);
        }
    } else {
        writeImageSeeds(seeds, extension);
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    if (const auto seeds = terrain::fuzz::seedFolder())
        writeSeeds(*seeds, fs::path(kInputFile).extension().string());
    return 0;
}

namespace {

// A block may decode to 64 MiB here, not the programs' 2 GiB (io::kDefaultMaxDecodeBytes):
// the check is the same comparison at either limit, but inputs that pass it just under
// 2 GiB cost a large part of a second each under AddressSanitizer: with tests/fuzz/dem-tiff/
// and the inputs mutated from them in its corpus, fuzz-dem-tiff reached 2.2 GB and ran 3 to
// 5 inputs a second, against about 390 without them (600 with them under this limit).
// 64 MiB still decodes a 65,536-column float32 scan-line block.
constexpr std::uint64_t kFuzzMaxDecodeBytes = std::uint64_t{64} << 20U;

terrain::io::DemOpenOptions fuzzOpenOptions() {
    terrain::io::DemOpenOptions options;
    options.maxDecodeBytes = kFuzzMaxDecodeBytes;
    return options;
}

// The windows a build starts with: the first rows, the last rows, a block in the middle.
void readFirstWindows(terrain::io::DemReader& dem) {
    const terrain::io::DemInfo& info = dem.info();
    constexpr std::int64_t kMaxColumns = 256, kMaxRows = 16;
    const std::int64_t columns = std::min(info.width, kMaxColumns);
    const std::int64_t rows = std::min(info.height, kMaxRows);
    std::vector<float> window(static_cast<std::size_t>(columns * rows));
    const std::array<std::array<std::int64_t, 2>, 3> corners{{
        {0, 0},
        {info.width - columns, info.height - rows},
        {(info.width - columns) / 2, (info.height - rows) / 2},
    }};
    for (const auto& [x0, y0] : corners) {
        if (!dem.readWindow(x0, y0, columns, rows, window)) break;
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace terrain;
    const fs::path file = fuzz::scratch() / kInputFile;
    fuzz::writeFile(file, std::span(data, size));
    auto opened = io::openDem({file.string()}, fuzzOpenOptions());
    if (!opened) return 0;
    io::DemReader& dem = *opened.value();
    const io::DemInfo& info = dem.info();
    fuzz::require(info.width > 0 && info.height > 0, "an opened DEM has samples");
    readFirstWindows(dem);
    // As a globe build opens it: a projected one onto a longitude/latitude grid, its own
    // samples placed through the CRS.
    if (info.georeference.crsKind != io::CrsKind::Projected &&
        !(info.georeference.crsKind == io::CrsKind::Geographic && info.resampledFrom))
        return 0;
    io::DemOpenOptions onTheGlobe = fuzzOpenOptions();
    onTheGlobe.geographicGrid = true;
    opened.value().reset();
    auto globe = io::openDem({file.string()}, onTheGlobe);
    if (!globe) return 0;
    io::DemReader& geographic = *globe.value();
    fuzz::require(geographic.info().width > 0 && geographic.info().height > 0,
                  "an opened DEM has samples");
    readFirstWindows(geographic);
    if (io::DemReader* own = geographic.originalSamples(); own != nullptr) {
        const std::int64_t columns = std::min<std::int64_t>(own->info().width, 256);
        std::vector<double> x(static_cast<std::size_t>(columns)), y(x.size());
        (void)geographic.placeOriginalSamples(0, 0, x, y);
    }
    return 0;
}
