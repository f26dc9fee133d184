// DEM reader through OpenImageIO: GeoTIFF/TIFF (striped or tiled, BigTIFF), PNG, OpenEXR
// and JPEG height maps. One ImageInput stays open for the reader's life; a window is
// served from decoded blocks (the file's tiles, or groups of rows for scanline files)
// kept in an LRU cache, so a sequence of bands decodes each block about once. TIFF files
// are first checked with libtiff (TiffDemInspection.h), which also gives the GeoTIFF
// georeference, GDAL no-data value and scale/offset that OpenImageIO 2.4 does not read;
// PNG and JPEG files are checked for truncation (ImageFileTruncation.h).
#include "terrain/dem/OpenDem.h"
#include "terrain/pyramid/ExrHeaderCheck.h"

#include "DemBlockCache.h"
#include "DemReaderFactories.h"
#include "terrain/source/DemSampleConversion.h"
#include "GdalSession.h"
#include "ImageFileTruncation.h"
#include "TiffDemInspection.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace terrain::io::detail {

namespace {

// Row groups of scanline files: enough rows that a band costs few decoder calls, few
// enough that a block of a 16k-wide raster stays a few MiB.
constexpr std::int64_t kScanlineBlockRows = 64;
constexpr std::int64_t kMaxScanlineBlockRows = 256;
constexpr std::size_t kMinCacheBytes = std::size_t{64} << 20U;
constexpr std::size_t kCachedBlockRows = 3;  // block rows of the whole width that fit
// OpenImageIO decodes scan-line files in chunks of up to 256 rows of the whole width (every
// channel, at least 4 bytes a sample), and a tiled file a row of tiles at a time; either
// must fit DemOpenOptions::maxDecodeBytes.
constexpr std::uint64_t kDecoderChunkRows = 256;
// The largest tile side we read beyond the image's own size (rounded up to the 16 samples
// TIFF tiles are multiples of): writers use 256 or 512; OpenImageIO allocates and clears a
// whole tile before decoding it, so a 1.4 KB TIFF whose header claims 8448 × 46336 tiles for
// a 46 × 12 image made it fill 1.5 GB (16 s under ASan, found by fuzz-dem-tiff).
constexpr std::int64_t kMaxTileSide = 4096;

// Bytes one row of `columns` samples of `spec` decodes to, all channels.
std::uint64_t decodedRowBytes(const OIIO::ImageSpec& spec, std::int64_t columns) {
    const std::uint64_t sampleBytes =
        std::max<std::uint64_t>(4, spec.channelformat(0).size()) * std::uint64_t(spec.nchannels);
    return std::uint64_t(columns) * sampleBytes;
}

// Our names for the source sample types, nullptr for ones that are not heights.
const char* sampleTypeName(OIIO::TypeDesc::BASETYPE type) {
    switch (type) {
        case OIIO::TypeDesc::UINT8:
            return "uint8";
        case OIIO::TypeDesc::INT8:
            return "int8";
        case OIIO::TypeDesc::UINT16:
            return "uint16";
        case OIIO::TypeDesc::INT16:
            return "int16";
        case OIIO::TypeDesc::UINT32:
            return "uint32";
        case OIIO::TypeDesc::INT32:
            return "int32";
        case OIIO::TypeDesc::HALF:
            return "float16";
        case OIIO::TypeDesc::FLOAT:
            return "float32";
        case OIIO::TypeDesc::DOUBLE:
            return "float64";
        default:
            return nullptr;
    }
}

class OiioDemReader final : public DemReader {
public:
    OiioDemReader(DemInfo info, std::unique_ptr<OIIO::ImageInput> input,
                  const OIIO::ImageSpec& spec)
        : m_info(std::move(info)),
          m_input(std::move(input)),
          m_originX(spec.x),
          m_originY(spec.y),
          m_originZ(spec.z),
          m_tiled(spec.tile_width > 0 && spec.tile_height > 0),
          m_cache(0) {
        const OIIO::TypeDesc native = spec.channelformat(0);
        // Half floats widen to float in OpenImageIO; every other type is read as stored
        // and converted here, because OpenImageIO would normalise integers to [0, 1].
        m_readType = native.basetype == OIIO::TypeDesc::HALF
                         ? OIIO::TypeDesc(OIIO::TypeDesc::FLOAT)
                         : OIIO::TypeDesc(static_cast<OIIO::TypeDesc::BASETYPE>(native.basetype));
        if (m_tiled) {
            m_blockWidth = spec.tile_width;
            m_blockHeight = spec.tile_height;
        } else {
            m_blockWidth = m_info.width;
            const int rowsPerStrip = spec.get_int_attribute("tiff:RowsPerStrip", 0);
            if (rowsPerStrip > 0 && rowsPerStrip <= kMaxScanlineBlockRows)
                m_blockHeight =
                    rowsPerStrip * std::max<std::int64_t>(1, kScanlineBlockRows / rowsPerStrip);
            else if (rowsPerStrip > kMaxScanlineBlockRows)
                m_blockHeight = kMaxScanlineBlockRows;
            else
                m_blockHeight = kScanlineBlockRows;
            m_blockHeight = std::min(m_blockHeight, m_info.height);
        }
        const auto blockRowBytes =
            static_cast<std::size_t>(m_info.width * m_blockHeight) * sizeof(float);
        m_cache = DemBlockCache(std::max(kMinCacheBytes, kCachedBlockRows * blockRowBytes));
    }

    const DemInfo& info() const override { return m_info; }

    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        assertDemWindow(m_info, x0, y0, width, rows, out);
        if (width == 0 || rows == 0) return {};
        const std::int64_t bx0 = x0 / m_blockWidth, bx1 = (x0 + width - 1) / m_blockWidth;
        const std::int64_t by0 = y0 / m_blockHeight, by1 = (y0 + rows - 1) / m_blockHeight;
        for (std::int64_t by = by0; by <= by1; ++by) {
            std::int64_t bx = bx0;
            while (bx <= bx1) {
                if (const std::vector<float>* block = m_cache.find(bx, by)) {
                    copyBlock(*block, bx, by, x0, y0, width, rows, out);
                    ++bx;
                    continue;
                }
                // The run of missing blocks in one decoder call (for tiles: one
                // read_tiles over the run, which reads the tiles in file order).
                std::int64_t end = bx + 1;
                while (end <= bx1 && m_cache.find(end, by) == nullptr) ++end;
                if (Status s = decodeRun(bx, end, by, x0, y0, width, rows, out); !s) return s;
                bx = end;
            }
        }
        return {};
    }

private:
    std::int64_t blockWidthAt(std::int64_t bx) const {
        return std::min(m_blockWidth, m_info.width - bx * m_blockWidth);
    }
    std::int64_t blockHeightAt(std::int64_t by) const {
        return std::min(m_blockHeight, m_info.height - by * m_blockHeight);
    }

    // Copies the part of block (bx, by) inside the window into out.
    void copyBlock(const std::vector<float>& block, std::int64_t bx, std::int64_t by,
                   std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                   std::span<float> out) const {
        const std::int64_t bw = blockWidthAt(bx);
        const std::int64_t left = bx * m_blockWidth, top = by * m_blockHeight;
        const std::int64_t cx0 = std::max(x0, left), cx1 = std::min(x0 + width, left + bw);
        const std::int64_t cy0 = std::max(y0, top),
                           cy1 = std::min(y0 + rows, top + blockHeightAt(by));
        for (std::int64_t y = cy0; y < cy1; ++y) {
            std::copy_n(block.data() + (y - top) * bw + (cx0 - left), cx1 - cx0,
                        out.data() + (y - y0) * width + (cx0 - x0));
        }
    }

    Status decodeRun(std::int64_t bxBegin, std::int64_t bxEnd, std::int64_t by, std::int64_t x0,
                     std::int64_t y0, std::int64_t width, std::int64_t rows, std::span<float> out) {
        const std::int64_t left = bxBegin * m_blockWidth;
        const std::int64_t right = std::min(bxEnd * m_blockWidth, m_info.width);
        const std::int64_t top = by * m_blockHeight;
        const std::int64_t bottom = top + blockHeightAt(by);
        const std::int64_t runWidth = right - left;
        const std::size_t pixelBytes = m_readType.size();
        m_raw.resize(static_cast<std::size_t>(runWidth * (bottom - top)) * pixelBytes);
        // Once GDAL is registered it owns libtiff's global error handler (CPLError), so
        // libtiff's complaints while OpenImageIO decodes arrive there.
        GdalErrorCapture libtiffErrors;
        bool ok = false;
        if (m_tiled) {
            ok = m_input->read_tiles(
                0, 0, static_cast<int>(m_originX + left), static_cast<int>(m_originX + right),
                static_cast<int>(m_originY + top), static_cast<int>(m_originY + bottom), m_originZ,
                m_originZ + 1, 0, 1, m_readType, m_raw.data());
        } else {
            ok = m_input->read_scanlines(0, 0, static_cast<int>(m_originY + top),
                                         static_cast<int>(m_originY + bottom), m_originZ, 0, 1,
                                         m_readType, m_raw.data());
        }
        if (!ok) {
            std::string message = m_input->geterror();
            if (message.empty())
                message = libtiffErrors.message("the decoder failed without a message");
            return Error{fmt::format("{}: cannot read rows {}..{}: {}", m_info.path, top,
                                     bottom - 1, libraryMessage(message, m_info.path))};
        }
        for (std::int64_t bx = bxBegin; bx < bxEnd; ++bx) {
            const std::int64_t bw = blockWidthAt(bx), bh = bottom - top;
            std::vector<float> block(static_cast<std::size_t>(bw * bh));
            for (std::int64_t r = 0; r < bh; ++r) {
                const std::size_t sourceSample =
                    static_cast<std::size_t>(r * runWidth + (bx * m_blockWidth - left));
                convertRow(m_raw.data() + sourceSample * pixelBytes, static_cast<std::size_t>(bw),
                           block.data() + r * bw);
            }
            copyBlock(block, bx, by, x0, y0, width, rows, out);
            m_cache.insert(bx, by, std::move(block));
        }
        return {};
    }

    void convertRow(const unsigned char* raw, std::size_t count, float* out) const {
        const auto run = [&](auto tag) {
            using T = decltype(tag);
            convertDemSamples(reinterpret_cast<const T*>(raw), count, out, m_info.vertical,
                              m_info.noDataValue);
        };
        switch (m_readType.basetype) {
            case OIIO::TypeDesc::UINT8:
                run(std::uint8_t{});
                break;
            case OIIO::TypeDesc::INT8:
                run(std::int8_t{});
                break;
            case OIIO::TypeDesc::UINT16:
                run(std::uint16_t{});
                break;
            case OIIO::TypeDesc::INT16:
                run(std::int16_t{});
                break;
            case OIIO::TypeDesc::UINT32:
                run(std::uint32_t{});
                break;
            case OIIO::TypeDesc::INT32:
                run(std::int32_t{});
                break;
            case OIIO::TypeDesc::DOUBLE:
                run(double{});
                break;
            default:
                run(float{});
                break;
        }
    }

    DemInfo m_info;
    std::unique_ptr<OIIO::ImageInput> m_input;
    int m_originX = 0, m_originY = 0, m_originZ = 0;  // the data window's corner
    bool m_tiled = false;
    std::int64_t m_blockWidth = 1, m_blockHeight = 1;
    OIIO::TypeDesc m_readType;
    DemBlockCache m_cache;
    std::vector<unsigned char> m_raw;  // one decoded run, in m_readType
};

}  // namespace

DemReaderResult openOiioDem(const std::string& path, const DemOpenOptions& options) {
    const Result<std::uint64_t> size = checkDemInputFile(path);
    if (!size) return size.error();
    const auto fail = [&](const std::string& what) {
        return Error{fmt::format("{}: {}", path, what)};
    };

    std::optional<TiffDemFacts> tiffFacts;
    const std::string ext = lowerExtension(path);
    if (ext == ".tif" || ext == ".tiff") {
        Result<TiffDemFacts> facts = inspectTiffDem(path, size.value());
        if (!facts) return facts.error();
        tiffFacts = std::move(facts).value();
        // GDAL reads flipped grids (and refuses rotated ones with its geotransform), and
        // chooses among bands.
        if (tiffFacts->flippedOrRotated || tiffFacts->samplesPerPixel > 1)
            return openGdalDem(path, options);
    }
    const bool jpeg = ext == ".jpg" || ext == ".jpeg" || ext == ".jpe";
    std::optional<std::string> truncated;
    if (ext == ".png") truncated = findPngTruncation(path, size.value());
    if (jpeg) truncated = findJpegTruncation(path, size.value());
    if (truncated) return fail(*truncated);
    if (ext == ".exr") {
        if (Status header = checkExrHeaderSizes(path); !header) return fail(header.error().message);
    }

    GdalErrorCapture libtiffErrors;  // see decodeRun
    std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path);
    if (!input) {
        std::string message = OIIO::geterror();
        if (message.empty()) message = "OpenImageIO cannot open it";
        return fail(libraryMessage(message, path));
    }
    const OIIO::ImageSpec spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        return fail(fmt::format("empty image ({} × {}, {} channels)", spec.width, spec.height,
                                spec.nchannels));
    if (spec.depth > 1)
        return fail(fmt::format("volume images (depth {}) are not DEMs", spec.depth));
    // Several channels in a PNG or JPEG (RGB, grey and alpha) are bands: GDAL chooses one and
    // says which. OpenEXR's channels are not bands; its first is read.
    if (spec.nchannels > 1 && ext != ".exr") {
        input->close();
        return openGdalDem(path, options);
    }
    const OIIO::TypeDesc native = spec.channelformat(0);
    const char* typeName = sampleTypeName(static_cast<OIIO::TypeDesc::BASETYPE>(native.basetype));
    if (typeName == nullptr)
        return fail(fmt::format("unsupported sample type: {}", native.c_str()));
    // Fewer bits than the type (1-, 2-, 4-, 12-bit files) are widened and rescaled by
    // OpenImageIO, which no longer gives the stored values.
    const int bits = spec.get_int_attribute("oiio:BitsPerSample", 0);
    if (bits != 0 && static_cast<std::size_t>(bits) != native.size() * 8)
        return fail(
            fmt::format("unsupported sample type: {}-bit samples (widened to {})", bits, typeName));

    const bool tiled = spec.tile_width > 0 && spec.tile_height > 0;
    const auto roundUp16 = [](std::int64_t v) { return (v + 15) / 16 * 16; };
    if (tiled && (spec.tile_width > std::max(kMaxTileSide, roundUp16(spec.width)) ||
                  spec.tile_height > std::max(kMaxTileSide, roundUp16(spec.height))))
        return fail(
            fmt::format("tiles of {} × {} for a {} × {} image: a tile may be larger than the image "
                        "(rounded up to 16) only up to {} on a side (a damaged header?)",
                        spec.tile_width, spec.tile_height, spec.width, spec.height, kMaxTileSide));
    // A row of tiles decodes whole tiles, past the image's right edge too.
    const std::int64_t rowColumns =
        tiled ? (std::int64_t{spec.width} + spec.tile_width - 1) / spec.tile_width * spec.tile_width
              : spec.width;
    const std::uint64_t rowBytes = decodedRowBytes(spec, rowColumns);
    const std::uint64_t blockRows = tiled ? std::uint64_t(spec.tile_height) : kDecoderChunkRows;
    if (rowBytes * blockRows > options.maxDecodeBytes)
        return fail(fmt::format(
            "{} × {} samples of {} channels: a {} decodes to {} MiB, more "
            "than the {} MiB a read may take (a damaged header?)",
            spec.width, spec.height, spec.nchannels, tiled ? "row of tiles" : "block of 256 rows",
            (rowBytes * blockRows) >> 20U, options.maxDecodeBytes >> 20U));

    DemInfo info;
    info.path = path;
    info.readerName = "oiio";
    info.inputs = {path};
    if (spec.nchannels > 1) {  // OpenEXR: its first channel, said
        info.bandCount = spec.nchannels;
        info.warnings.push_back(fmt::format(
            "{}: {} channels; heights are read from the first ({})", path, spec.nchannels,
            spec.channelnames.empty() ? std::string("unnamed") : spec.channelnames.front()));
    }
    info.width = spec.width;
    info.height = spec.height;
    info.sampleType = typeName;
    info.georeference.crsKind = CrsKind::Unknown;
    if (tiffFacts) {
        if (tiffFacts->georeference) {
            info.georeference = *tiffFacts->georeference;
            info.hasGeoreference = true;
        }
        info.noDataValue = tiffFacts->noDataValue;
        if (tiffFacts->scale && *tiffFacts->scale != 0.0) info.vertical.scale = *tiffFacts->scale;
        if (tiffFacts->offset) info.vertical.offset = *tiffFacts->offset;
    }
    if (Status s = applyDemOpenOptions(info, options); !s) return s.error();
    return std::unique_ptr<DemReader>(
        std::make_unique<OiioDemReader>(std::move(info), std::move(input), spec));
}

}  // namespace terrain::io::detail
