// OpenEXR file layout ("OpenEXR File Layout", openexr.com): magic 20000630 (76 2f 31 01),
// a 4-byte version field (version 2 in the low byte; flags: 0x200 single-part tiled,
// 0x400 long names, 0x800 deep data, 0x1000 multi-part), then the header(s), then the
// chunk offset tables (8 bytes per chunk) and the chunks.
//
// OpenEXR reads the value of a type it knows in that type's own layout, whatever the size
// field says (a chlist runs to its empty name, a box2i is 16 bytes), so a walk that skipped
// by size alone would lose step with it: the walk reads those values as OpenEXR does and
// requires them to fill their size exactly.
//
// A header can also declare far more pixels than its file could decode to: a 232-byte file
// with an 8.4M × 9 data window makes OpenEXR and OpenImageIO allocate and fill 300 MB (40 s
// under ASan) before the chunks turn out to be missing. No codec expands its input more
// than a known ratio, so the pixels of a data window must fit in the file size times the
// ratio of its compression (kMaxExpansion below).
#include "terrain/pyramid/ExrHeaderCheck.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace terrain::io {

namespace {

constexpr std::uint32_t kMagic = 20000630;
constexpr std::uint32_t kMultiPartFlag = 0x1000;
constexpr std::uint32_t kLongNamesFlag = 0x400;
constexpr std::uint32_t kDeepFlag = 0x800;
constexpr std::uint64_t kChunkOffsetBytes = 8;

struct FixedSize {
    std::string_view type;
    std::int32_t bytes;
};
// Every fixed-size attribute type of OpenEXR 3.1.
constexpr std::array<FixedSize, 24> kFixedSizes{{
    {"box2i", 16},      {"box2f", 16},
    {"compression", 1}, {"lineOrder", 1},
    {"envmap", 1},      {"deepImageState", 1},
    {"float", 4},       {"int", 4},
    {"double", 8},      {"v2i", 8},
    {"v2f", 8},         {"v2d", 16},
    {"v3i", 12},        {"v3f", 12},
    {"v3d", 24},        {"m33f", 36},
    {"m33d", 72},       {"m44f", 64},
    {"m44d", 128},      {"chromaticities", 32},
    {"tiledesc", 9},    {"rational", 8},
    {"keycode", 28},    {"timecode", 8},
}};

std::optional<std::int32_t> fixedSizeOf(std::string_view type) {
    for (const FixedSize& f : kFixedSizes)
        if (f.type == type) return f.bytes;
    return std::nullopt;
}

// OpenEXR's Header() defaults to ZIP_COMPRESSION, and a header without a compression
// attribute keeps that default (ImfHeader.h).
constexpr int kDefaultCompression = 3;

// Scan lines per chunk of a scan-line part, by compression (ImfCompression.h order).
std::int64_t linesPerChunk(int compression) {
    constexpr std::array<std::int64_t, 10> kLines{1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
    return compression >= 0 && compression < 10 ? kLines[static_cast<std::size_t>(compression)] : 1;
}

// The most bytes of pixels one byte of a chunk can decode to, by compression (ImfCompression.h
// order), rounded up; a compression OpenEXR does not know gets the largest.
//   NONE   1      chunks hold the pixels as they are.
//   RLE    64     a count byte and one value byte stand for at most 128 bytes.
//   ZIPS   1032   deflate's limit (zlib FAQ: "the limit is 1032:1"); OpenEXR's predictor
//   ZIP    1032   and byte reordering keep the size.
//   PIZ    512    OpenEXR's Huffman coder codes a run of up to 256 16-bit values as the
//                 value's code, the run code and an 8-bit count: 4096 bits in ≥ 10 bits.
//   PXR24  1376   floats cut to 24 bits (4/3), then deflate.
//   B44    11     a 4×4 block of halves (32 bytes) in 14 bytes, or 3 bytes when flat (B44A);
//   B44A   11     other channel types are stored as they are.
//   DWAA   66048  lossless channels: deflate; DCT channels: an 8×8 block of halves (128
//   DWAB   66048  bytes) as at least a 2-byte DC and a 2-byte end of block, then deflate: at
//                 most 32 × 1032, doubled for the RLE class.
constexpr std::array<std::uint64_t, 10> kMaxExpansion{1,    64, 1032, 1032,  512,
                                                      1376, 11, 11,   66048, 66048};
std::string_view compressionName(int compression) {
    constexpr std::array<std::string_view, 10> kNames{"none",  "RLE", "ZIPS", "ZIP",  "PIZ",
                                                      "PXR24", "B44", "B44A", "DWAA", "DWAB"};
    return compression >= 0 && compression < 10 ? kNames[static_cast<std::size_t>(compression)]
                                                : "unknown";
}
std::uint64_t maxExpansion(int compression) {
    return compression >= 0 && compression < 10
               ? kMaxExpansion[static_cast<std::size_t>(compression)]
               : kMaxExpansion[8];
}

std::uint32_t littleEndian32(const unsigned char* b) {
    return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8U | std::uint32_t{b[2]} << 16U |
           std::uint32_t{b[3]} << 24U;
}

// What one header says about the size of its chunk offset table.
struct PartFacts {
    bool hasDataWindow = false;
    std::int32_t window[4] = {0, 0, 0, 0};  // xMin, yMin, xMax, yMax
    bool tiled = false;
    std::uint32_t tileX = 0, tileY = 0;
    int compression = kDefaultCompression;
    std::optional<std::int32_t> chunkCount;
    bool deep = false;  // deep parts hold a variable number of samples per pixel
    struct Channel {
        std::int64_t bytes;  // per sample: UINT and FLOAT 4, HALF 2
        std::int64_t xSampling, ySampling;
    };
    std::vector<Channel> channels;

    // The fewest bytes the data window's pixels decode to: every channel's samples (each
    // sampling rounded down, so the count is never over). In double: 2^32 columns times
    // 2^32 rows would overflow 64 bits.
    double decodedBytes(std::int64_t w, std::int64_t h) const {
        double sum = 0;
        for (const Channel& c : channels)
            sum += static_cast<double>(c.bytes) * static_cast<double>(w / c.xSampling) *
                   static_cast<double>(h / c.ySampling);
        return sum;
    }
};

class HeaderWalk {
public:
    HeaderWalk(std::istream& in, std::uintmax_t fileSize, std::size_t maxName)
        : m_in(in), m_fileSize(fileSize), m_maxName(maxName) {}

    std::uintmax_t left() const {
        const auto at = static_cast<std::uintmax_t>(m_in.tellg());
        return at <= m_fileSize ? m_fileSize - at : 0;
    }
    bool bytes(void* out, std::size_t n) {
        return static_cast<bool>(
            m_in.read(static_cast<char*>(out), static_cast<std::streamsize>(n)));
    }
    bool i32(std::int32_t& v) {
        unsigned char b[4];
        if (!bytes(b, 4)) return false;
        v = static_cast<std::int32_t>(littleEndian32(b));
        return true;
    }
    // A null-terminated name of at most m_maxName characters.
    bool name(std::string& out) {
        out.clear();
        for (char c = 0; m_in.get(c);) {
            if (c == '\0') return true;
            if (out.size() == m_maxName) return false;
            out.push_back(c);
        }
        return false;
    }
    void skip(std::int64_t n) { m_in.seekg(n, std::ios::cur); }

    // A chlist as OpenEXR reads it: entries (name, 16 bytes: pixel type, pLinear, 3
    // reserved, x sampling, y sampling) until an empty name.
    std::optional<std::int64_t> channelList(std::vector<PartFacts::Channel>& channels) {
        std::int64_t consumed = 0;
        std::string channel;
        while (true) {
            if (!name(channel)) return std::nullopt;
            consumed += static_cast<std::int64_t>(channel.size()) + 1;
            if (channel.empty()) return consumed;
            unsigned char entry[16];
            if (!bytes(entry, sizeof entry)) return std::nullopt;
            consumed += 16;
            // Sampling below 1 is refused by OpenEXR; counting it as 1 keeps the count low
            // enough never to refuse a file OpenEXR reads. An unknown type counts as 2 bytes.
            const auto sampling = [](std::int32_t s) { return std::max<std::int64_t>(s, 1); };
            const std::uint32_t type = littleEndian32(entry);
            channels.push_back({type == 1 ? 2 : (type <= 2 ? 4 : 2),
                                sampling(static_cast<std::int32_t>(littleEndian32(entry + 8))),
                                sampling(static_cast<std::int32_t>(littleEndian32(entry + 12)))});
        }
    }

private:
    std::istream& m_in;
    std::uintmax_t m_fileSize;
    std::size_t m_maxName;
};

}  // namespace

Status checkExrHeaderSizes(const std::filesystem::path& path) {
    std::error_code ec;
    const std::uintmax_t fileSize = std::filesystem::file_size(path, ec);
    if (ec) return Error{"cannot read its size: " + ec.message()};
    std::ifstream in(path, std::ios::binary);
    return checkExrHeaderSizes(in, fileSize);
}

Status checkExrHeaderSizes(std::istream& in, std::uintmax_t fileSize) {
    unsigned char start[8] = {};
    if (!in.read(reinterpret_cast<char*>(start), sizeof start))
        return Error{"not an OpenEXR file: shorter than its 8-byte start"};
    if (littleEndian32(start) != kMagic) return Error{"not an OpenEXR file: no magic number"};
    const std::uint32_t version = littleEndian32(start + 4);
    const bool multiPart = (version & kMultiPartFlag) != 0;
    HeaderWalk walk(in, fileSize, (version & kLongNamesFlag) != 0 ? 255 : 31);

    std::string name, type;
    for (int part = 0;; ++part) {
        if (multiPart && part > 0 && in.peek() == 0) break;  // the empty header after the last
        const auto corrupt = [&](const std::string& what) {
            return Error{fmt::format("corrupt OpenEXR header {}: {}", part, what)};
        };
        PartFacts facts;
        facts.deep = (version & kDeepFlag) != 0;  // a single-part deep file
        while (true) {                            // one header: attributes until an empty name
            if (!walk.name(name))
                return corrupt(
                    "an attribute name runs past the end of the file or its length "
                    "limit");
            if (name.empty()) break;
            if (!walk.name(type)) return corrupt(fmt::format("attribute '{}' has no type", name));
            std::int32_t size = 0;
            if (!walk.i32(size)) return corrupt(fmt::format("attribute '{}' has no size", name));
            if (size < 0 || static_cast<std::uintmax_t>(size) > walk.left())
                return corrupt(
                    fmt::format("attribute '{}' ({}) says it has {} bytes, the file "
                                "has {} left",
                                name, type, size, walk.left()));
            const auto wrongSize = [&](std::int64_t actual) {
                return corrupt(
                    fmt::format("attribute '{}' ({}) says it has {} bytes, its value "
                                "has {}",
                                name, type, size, actual));
            };
            if (const std::optional<std::int32_t> fixed = fixedSizeOf(type)) {
                if (size != *fixed) return wrongSize(*fixed);
                if (name == "dataWindow" && type == "box2i") {
                    for (std::int32_t& v : facts.window)
                        if (!walk.i32(v)) return corrupt("dataWindow is cut short");
                    facts.hasDataWindow = true;
                } else if (name == "tiles" && type == "tiledesc") {
                    unsigned char tiles[9];
                    if (!walk.bytes(tiles, sizeof tiles)) return corrupt("tiles is cut short");
                    facts.tiled = true;
                    facts.tileX = littleEndian32(tiles);
                    facts.tileY = littleEndian32(tiles + 4);
                } else if (name == "compression" && type == "compression") {
                    unsigned char c = 0;
                    if (!walk.bytes(&c, 1)) return corrupt("compression is cut short");
                    facts.compression = c;
                } else if (name == "chunkCount" && type == "int") {
                    std::int32_t count = 0;
                    if (!walk.i32(count)) return corrupt("chunkCount is cut short");
                    facts.chunkCount = count;
                } else {
                    walk.skip(size);
                }
            } else if (type == "chlist") {
                facts.channels.clear();
                const std::optional<std::int64_t> consumed = walk.channelList(facts.channels);
                if (!consumed) return corrupt("the channel list runs past the end of the file");
                if (*consumed != size) return wrongSize(*consumed);
            } else if (type == "preview") {
                std::int32_t w = 0, h = 0;
                if (size < 8 || !walk.i32(w) || !walk.i32(h)) return wrongSize(8);
                // 4 · w · h of two unsigned 32-bit sides can pass 2^63: such a preview is
                // larger than any attribute and is refused before it is multiplied out.
                const std::uint64_t width = static_cast<std::uint32_t>(w);
                const std::uint64_t height = static_cast<std::uint32_t>(h);
                if (height != 0 && width > (std::uint64_t{1} << 60) / height)
                    return corrupt(fmt::format("attribute '{}' (preview) claims {} × {} pixels",
                                               name, width, height));
                const auto pixels = static_cast<std::int64_t>(8 + 4 * width * height);
                if (pixels != size) return wrongSize(pixels);
                walk.skip(size - 8);
            } else if (type == "stringvector") {
                // Length-prefixed strings, each allocated at its stated length.
                for (std::int64_t read = 0; read < size;) {
                    std::int32_t length = 0;
                    if (size - read < 4 || !walk.i32(length) || length < 0 ||
                        length > size - read - 4)
                        return corrupt(
                            fmt::format("a string of attribute '{}' runs past the "
                                        "attribute",
                                        name));
                    walk.skip(length);
                    read += 4 + length;
                }
            } else {
                if (name == "type" && type == "string") {
                    std::string partType(static_cast<std::size_t>(size), '\0');
                    if (!walk.bytes(partType.data(), partType.size()))
                        return corrupt("type is cut short");
                    facts.deep = partType.rfind("deep", 0) == 0;
                } else {
                    walk.skip(size);  // strings, vectors and opaque types: read at their size
                }
            }
        }
        // The chunk offset table OpenEXR allocates from this header must fit in the file.
        const std::uint64_t room = fileSize / kChunkOffsetBytes;
        if (facts.chunkCount &&
            (*facts.chunkCount < 0 || static_cast<std::uint64_t>(*facts.chunkCount) > room))
            return corrupt(fmt::format("chunkCount {} does not fit in a file of {} bytes",
                                       *facts.chunkCount, fileSize));
        if (facts.hasDataWindow) {
            const std::int64_t w = std::int64_t{facts.window[2]} - facts.window[0] + 1;
            const std::int64_t h = std::int64_t{facts.window[3]} - facts.window[1] + 1;
            if (w < 1 || h < 1) return corrupt(fmt::format("the data window is {} × {}", w, h));
            std::uint64_t chunks = 0;
            if (facts.tiled) {
                if (facts.tileX == 0 || facts.tileY == 0) return corrupt("a tile size is 0");
                chunks = static_cast<std::uint64_t>((w + facts.tileX - 1) / facts.tileX) *
                         static_cast<std::uint64_t>((h + facts.tileY - 1) / facts.tileY);
            } else {
                const std::int64_t lines = linesPerChunk(facts.compression);
                chunks = static_cast<std::uint64_t>((h + lines - 1) / lines);
            }
            if (chunks > room)
                return corrupt(
                    fmt::format("a {} × {} data window needs {} chunks, more than a "
                                "file of {} bytes can hold",
                                w, h, chunks, fileSize));
            // A deep part holds a varying number of samples per pixel: no fixed size.
            const double limit = static_cast<double>(fileSize) *
                                 static_cast<double>(maxExpansion(facts.compression));
            if (const double decoded = facts.decodedBytes(w, h); !facts.deep && decoded > limit)
                return corrupt(fmt::format(
                    "its {} × {} data window ({} channels) decodes to {:.0f} bytes; {} bytes "
                    "compressed with {} decode to at most {:.0f}",
                    w, h, facts.channels.size(), decoded, fileSize,
                    compressionName(facts.compression), limit));
        }
        if (!multiPart) break;
    }
    return {};
}

}  // namespace terrain::io
