// Imagery tile files (ImageryTileFormat.h): little-endian header and table, WebP payloads.
#include "ImageryTileFormat.h"

#include <fmt/format.h>
#include <webp/decode.h>
#include <webp/encode.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>

namespace terrain::io::imagery {
namespace {

void put32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t v) {
    for (std::size_t b = 0; b < 4; ++b) out[at + b] = static_cast<std::uint8_t>(v >> (8U * b));
}
void put64(std::vector<std::uint8_t>& out, std::size_t at, std::uint64_t v) {
    for (std::size_t b = 0; b < 8; ++b) out[at + b] = static_cast<std::uint8_t>(v >> (8U * b));
}
std::uint32_t get32(std::span<const std::uint8_t> in, std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t b = 0; b < 4; ++b) v |= std::uint32_t{in[at + b]} << (8U * b);
    return v;
}
std::uint64_t get64(std::span<const std::uint8_t> in, std::size_t at) {
    std::uint64_t v = 0;
    for (std::size_t b = 0; b < 8; ++b) v |= std::uint64_t{in[at + b]} << (8U * b);
    return v;
}

// Header fields' offsets.
constexpr std::size_t kVersionAt = 8, kLevelAt = 12, kGroupXAt = 16, kGroupYAt = 24,
                      kGroupTilesAt = 32, kTexelsAt = 36, kCodecAt = 40, kCrcAt = 44;

std::uint32_t tableCrc(std::span<const std::uint8_t> head) {
    uLong crc = crc32_z(0L, Z_NULL, 0);
    crc = crc32_z(crc, head.data(), kCrcAt);
    crc = crc32_z(crc, head.data() + kHeaderBytes, kTableEnd - kHeaderBytes);
    return static_cast<std::uint32_t>(crc);
}

}  // namespace

GroupId groupOf(const PatchId& id) { return {id.level, id.x / kGroupTiles, id.y / kGroupTiles}; }

int indexInGroup(const PatchId& id) {
    return static_cast<int>((id.y % kGroupTiles) * kGroupTiles + id.x % kGroupTiles);
}

std::filesystem::path groupPath(const GroupId& g) {
    return std::filesystem::path(fmt::format("L{}", g.level)) / std::to_string(g.y) /
           (std::to_string(g.x) + ".tiles");
}

std::uint32_t crc32Of(std::span<const std::uint8_t> bytes) {
    return static_cast<std::uint32_t>(crc32_z(crc32_z(0L, Z_NULL, 0), bytes.data(), bytes.size()));
}

std::vector<std::uint8_t> encodeTable(const GroupTable& table) {
    std::vector<std::uint8_t> out(kTableEnd, 0);
    std::copy(kMagic.begin(), kMagic.end(), out.begin());
    put32(out, kVersionAt, kFormatVersion);
    put32(out, kLevelAt, static_cast<std::uint32_t>(table.group.level));
    put64(out, kGroupXAt, static_cast<std::uint64_t>(table.group.x));
    put64(out, kGroupYAt, static_cast<std::uint64_t>(table.group.y));
    put32(out, kGroupTilesAt, kGroupTiles);
    put32(out, kTexelsAt, kImageryTileTexels);
    put32(out, kCodecAt, kWebpCodec);
    for (std::size_t i = 0; i < table.entries.size(); ++i) {
        const TileEntry& e = table.entries[i];
        const std::size_t at = kHeaderBytes + i * kEntryBytes;
        put64(out, at, e.offset);
        put32(out, at + 8, e.size);
        put32(out, at + 12, e.crc32);
        out[at + 16] = e.info.present ? 1 : 0;
        out[at + 17] = e.info.presentChildren;
        out[at + 18] = e.info.opaque ? 1 : 0;
    }
    put32(out, kCrcAt, tableCrc(out));
    return out;
}

Result<GroupTable> decodeTable(std::span<const std::uint8_t> head, std::uint64_t fileBytes) {
    if (head.size() < kTableEnd || fileBytes < kTableEnd)
        return Error{fmt::format("truncated: {} bytes, shorter than the {}-byte header and table",
                                 std::min<std::uint64_t>(head.size(), fileBytes), kTableEnd)};
    if (!std::equal(kMagic.begin(), kMagic.end(), head.begin()))
        return Error{"not an imagery tile file (bad magic)"};
    if (const std::uint32_t v = get32(head, kVersionAt); v != kFormatVersion)
        return Error{
            fmt::format("format version {}; this reader reads version {}", v, kFormatVersion)};
    if (get32(head, kCrcAt) != tableCrc(head))
        return Error{"corrupt header or tile table (CRC-32 mismatch)"};
    if (get32(head, kGroupTilesAt) != kGroupTiles || get32(head, kTexelsAt) != kImageryTileTexels ||
        get32(head, kCodecAt) != kWebpCodec)
        return Error{fmt::format("unsupported layout: {} tiles a side, {} texels, codec {}",
                                 get32(head, kGroupTilesAt), get32(head, kTexelsAt),
                                 get32(head, kCodecAt))};
    GroupTable table;
    table.group = {static_cast<int>(get32(head, kLevelAt)),
                   static_cast<std::int64_t>(get64(head, kGroupXAt)),
                   static_cast<std::int64_t>(get64(head, kGroupYAt))};
    for (std::size_t i = 0; i < table.entries.size(); ++i) {
        const std::size_t at = kHeaderBytes + i * kEntryBytes;
        TileEntry& e = table.entries[i];
        e.offset = get64(head, at);
        e.size = get32(head, at + 8);
        e.crc32 = get32(head, at + 12);
        const std::uint8_t present = head[at + 16], children = head[at + 17],
                           opaque = head[at + 18], reserved = head[at + 19];
        const bool bad = present > 1 || children > 15 || opaque > 1 || reserved != 0 ||
                         (present == 0 && (e.size != 0 || children != 0 || opaque != 0)) ||
                         (e.size == 0 && (e.offset != 0 || opaque != 0)) ||
                         (e.size != 0 && (e.offset < kTableEnd || e.offset > fileBytes ||
                                          e.size > fileBytes - e.offset));
        if (bad)
            return Error{fmt::format("corrupt tile table entry {} (tile {}, {} of the group)", i,
                                     i % kGroupTiles, i / kGroupTiles)};
        e.info = {present == 1, children, opaque == 1};
    }
    return table;
}

Result<std::vector<std::uint8_t>> encodeTexels(std::span<const std::uint8_t> rgba,
                                               const Encoding& encoding) {
    TERRAIN_ASSERT(rgba.size() == kImageryTileBytes, "a tile's texels");
    WebPConfig config;
    if (!WebPConfigInit(&config)) return Error{"WebP: library version mismatch"};
    config.lossless = encoding.lossless ? 1 : 0;
    config.quality = encoding.lossless ? 75.0f : static_cast<float>(encoding.quality);
    config.method = 4;
    // Lossless keeps the colour under alpha 0 too (a bit-exact round trip); lossy may change
    // it, where nothing shows.
    config.exact = encoding.lossless ? 1 : 0;
    WebPPicture picture;
    if (!WebPPictureInit(&picture)) return Error{"WebP: library version mismatch"};
    picture.use_argb = encoding.lossless ? 1 : 0;
    picture.width = kImageryTileTexels;
    picture.height = kImageryTileTexels;
    WebPMemoryWriter writer;
    WebPMemoryWriterInit(&writer);
    picture.writer = WebPMemoryWrite;
    picture.custom_ptr = &writer;
    Status status;
    if (!WebPPictureImportRGBA(&picture, rgba.data(), kImageryTileTexels * 4))
        status = Error{"WebP: out of memory importing a tile"};
    else if (!WebPEncode(&config, &picture))
        status = Error{
            fmt::format("WebP: encoding failed (error {})", static_cast<int>(picture.error_code))};
    std::vector<std::uint8_t> out;
    if (status) out.assign(writer.mem, writer.mem + writer.size);
    WebPPictureFree(&picture);
    WebPMemoryWriterClear(&writer);
    if (!status) return status.error();
    return out;
}

Status decodeTexels(std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& rgba) {
    int width = 0, height = 0;
    if (!WebPGetInfo(payload.data(), payload.size(), &width, &height))
        return Error{"corrupt WebP payload"};
    if (width != kImageryTileTexels || height != kImageryTileTexels)
        return Error{fmt::format("WebP payload of {} × {} texels, not {} × {}", width, height,
                                 kImageryTileTexels, kImageryTileTexels)};
    rgba.resize(kImageryTileBytes);
    if (!WebPDecodeRGBAInto(payload.data(), payload.size(), rgba.data(), rgba.size(),
                            kImageryTileTexels * 4))
        return Error{"corrupt WebP payload (does not decode)"};
    return {};
}

bool interiorOpaque(std::span<const std::uint8_t> rgba) {
    for (int r = kImageryBorderTexels; r < kImageryTileTexels - kImageryBorderTexels; ++r)
        for (int c = kImageryBorderTexels; c < kImageryTileTexels - kImageryBorderTexels; ++c)
            if (rgba[(static_cast<std::size_t>(r) * kImageryTileTexels +
                      static_cast<std::size_t>(c)) *
                         4 +
                     3] != 255)
                return false;
    return true;
}

bool fullyTransparent(std::span<const std::uint8_t> rgba) {
    for (std::size_t i = 3; i < rgba.size(); i += 4)
        if (rgba[i] != 0) return false;
    return true;
}

Status checkFile(std::span<const std::uint8_t> bytes) {
    const Result<GroupTable> table = decodeTable(bytes, bytes.size());
    if (!table) return table.error();
    std::vector<std::uint8_t> rgba;
    for (std::size_t i = 0; i < table.value().entries.size(); ++i) {
        const TileEntry& e = table.value().entries[i];
        if (e.size == 0) continue;
        const auto payload = bytes.subspan(static_cast<std::size_t>(e.offset), e.size);
        if (crc32Of(payload) != e.crc32)
            return Error{fmt::format("tile {} of the group: payload CRC-32 mismatch", i)};
        if (Status s = decodeTexels(payload, rgba); !s)
            return Error{fmt::format("tile {} of the group: {}", i, s.error().message)};
    }
    return {};
}

}  // namespace terrain::io::imagery
