// The structure of an imagery layer's tile files (docs/imagery.md, "Tile files"): header,
// tile table and WebP payloads, shared by the writer, the reader and the fuzz target so the
// three cannot drift apart. Pure functions on bytes: any thread.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace terrain::io::imagery {

inline constexpr std::array<std::uint8_t, 8> kMagic = {'T', 'R', 'I', 'M', 'A', 'G', 'E', '\n'};
inline constexpr std::uint32_t kFormatVersion = 1;
/// Tiles a side of one file, as the heights' shards group 16 × 16 patches.
inline constexpr int kGroupTiles = 16;
inline constexpr int kGroupTileCount = kGroupTiles * kGroupTiles;
inline constexpr std::uint32_t kWebpCodec = 1;
inline constexpr std::size_t kHeaderBytes = 48;
inline constexpr std::size_t kEntryBytes = 20;
inline constexpr std::size_t kTableEnd = kHeaderBytes + kGroupTileCount * kEntryBytes;
/// The layer's list of files (docs/imagery.md, "layer.json").
inline constexpr const char* kIndexFileName = "layer.json";

/// One tile's row of the table.
struct TileEntry {
    std::uint64_t offset = 0;  ///< of its payload from the file's start; 0 without one
    std::uint32_t size = 0;    ///< payload bytes; 0: absent, or present and fully transparent
    std::uint32_t crc32 = 0;   ///< CRC-32 (zlib) of the payload bytes
    ImageryTileInfo info;
    bool operator==(const TileEntry&) const = default;
};

/// Where a tile's file is: group (x / 16, y / 16) of its level.
struct GroupId {
    int level = 0;
    std::int64_t x = 0;
    std::int64_t y = 0;
    bool operator==(const GroupId&) const = default;
    auto operator<=>(const GroupId&) const = default;
};
GroupId groupOf(const PatchId& id);
/// The tile's index in its file's table: (y mod 16) · 16 + (x mod 16).
int indexInGroup(const PatchId& id);
/// "L<level>/<gy>/<gx>.tiles", relative to the layer folder.
std::filesystem::path groupPath(const GroupId& g);

/// A parsed file header and table.
struct GroupTable {
    GroupId group;
    std::array<TileEntry, kGroupTileCount> entries{};
};

/// Header and table bytes (kTableEnd of them) of `table`, with their CRC.
std::vector<std::uint8_t> encodeTable(const GroupTable& table);
/// Parses and checks the first kTableEnd bytes of a file of `fileBytes` bytes: magic,
/// version, codec, texels, the table's CRC, each entry's fields and that its payload lies
/// within the file after the table. The message says what is wrong, without the file name.
Result<GroupTable> decodeTable(std::span<const std::uint8_t> head, std::uint64_t fileBytes);

struct Encoding {
    bool lossless = false;
    int quality = 85;  ///< 0 … 100, lossy only
};
/// The WebP payload of kImageryTileTexels² RGBA8 texels (alpha kept; lossless keeps every
/// texel exactly, the colour under alpha 0 too).
Result<std::vector<std::uint8_t>> encodeTexels(std::span<const std::uint8_t> rgba,
                                               const Encoding& encoding);
/// Decodes a payload into `rgba` (resized to kImageryTileBytes). Errors say what is wrong.
Status decodeTexels(std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& rgba);

std::uint32_t crc32Of(std::span<const std::uint8_t> bytes);

/// Whether every interior texel has alpha 255; whether every texel has alpha 0.
bool interiorOpaque(std::span<const std::uint8_t> rgba);
bool fullyTransparent(std::span<const std::uint8_t> rgba);

/// Checks a whole tile file in memory: its table and every payload (CRC, decodes to a
/// tile of the right size). What terrain-inspect --verify and the fuzz target run.
Status checkFile(std::span<const std::uint8_t> bytes);

}  // namespace terrain::io::imagery
