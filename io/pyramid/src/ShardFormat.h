// The structure of a shard file (docs/pyramid-format.md, "Shard files"): part, channel and
// attribute names and the OpenEXR headers, shared by the shard writer and the reader so
// the two cannot drift apart.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/io/PatchRecord.h"
#include "terrain/io/PyramidLayout.h"

#include <ImfFrameBuffer.h>
#include <ImfHeader.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace terrain::io::shard {

/// 2: heights stored as height codes (HeightCodes.h) with a divisor per patch; 1 (pyramid
/// versions 2 and 3) stored them as floats.
inline constexpr int kFormatVersion = 2;

inline constexpr const char* kHeightsPart = "heights";
inline constexpr const char* kBlockErrorsPart = "blockErrors";
inline constexpr const char* kPatchInfoPart = "patchInfo";
inline constexpr int kHeightsIndex = 0;  // part order as written; readers look parts up by name
inline constexpr int kBlockErrorsIndex = 1;
inline constexpr int kPatchInfoIndex = 2;
inline constexpr int kPartCount = 3;

/// The height codes' low and high 16 bits, as HALF channels (the bits are not halves):
/// OpenEXR's ZIP splits a chunk's bytes into even and odd ones, so the high halves of
/// small codes, all zeros, end up apart from the low ones and cost nothing.
inline constexpr std::array<const char*, 2> kHeightCodeChannels = {"H0", "H1"};
inline constexpr const char* kMaskChannel = "V";
/// HALF: λ(d) rounded up to a half (io::roundUpToHalf), so a bound stays a bound in half
/// the bytes; the tessellation factors need no more than 11 bits of it.
inline constexpr std::array<const char*, 4> kBlockErrorChannels = {"L1", "L2", "L3", "L4"};

inline constexpr const char* kFormatVersionAttribute = "terrain:formatVersion";
inline constexpr const char* kLevelAttribute = "terrain:level";
inline constexpr const char* kShardAttribute = "terrain:shard";

/// Mask samples as stored (HALF bits of 1.0 and 0.0).
inline constexpr std::uint16_t kHalfOne = 0x3C00;
inline constexpr std::uint16_t kHalfZero = 0x0000;

/// The HALF slices of the height codes' channels over `codes` (uint32, row stride
/// `rowCodes`, y relative to the tile, x too if `xTileCoordinates`): each code's low 16
/// bits, then its high 16 bits, in place.
void insertHeightCodeSlices(Imf::FrameBuffer& frame, std::uint32_t* codes, std::size_t rowCodes,
                            bool xTileCoordinates);

/// One pixel of the patchInfo part, laid out for an OpenEXR frame buffer (xStride =
/// sizeof(StoredInfo)).
struct StoredInfo {
    std::uint32_t present = 0;
    float minHeight = 0.0f;
    float maxHeight = 0.0f;
    float error = 0.0f;
    float approxError = 0.0f;
    float quantError = 0.0f;
    std::uint32_t noDataSamples = 0;
    std::uint32_t crc32 = 0;
    std::uint32_t heightDivisor = 0;  ///< of the patch's height codes (HeightCodes.h)
};

/// The stored `present` channel: 0 absent; 1 + 2 · presentChildren present (planar
/// pyramids: always 0 or 1).
std::uint32_t storedPresent(const PatchInfo& info);
/// The largest `present` a format version allows: 1 (version 2), 31 (version 3).
inline constexpr std::uint32_t kMaxStoredPresentPlanar = 1;
inline constexpr std::uint32_t kMaxStoredPresentGlobe = 31;
/// The stored fields of `info`, with the divisor of the patch's height codes.
StoredInfo toStored(const PatchInfo& info, std::uint32_t heightDivisor);
PatchInfo fromStored(const StoredInfo& stored);

/// The three part headers of shard `s`, in part order. zipLevel is the writer's ephemeral
/// setting (not stored in the file); 0 means NO_COMPRESSION.
std::vector<Imf::Header> shardHeaders(const PyramidLayout& layout, const ShardId& s, bool withMask,
                                      int zipLevel);

/// Checks that `actual` (one part's header, found by name) has the structure of
/// `expected`: type, tiling, data window, channels and terrain attributes. The message
/// says what differs, without the file name.
Status checkPartHeader(const Imf::Header& actual, const Imf::Header& expected);

}  // namespace terrain::io::shard
