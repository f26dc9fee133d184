// The structure of a shard file (docs/pyramid-format.md, "Shard files"): part, channel and
// attribute names and the OpenEXR headers, shared by the shard writer and the reader so
// the two cannot drift apart.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <ImfDeepFrameBuffer.h>
#include <ImfHeader.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace terrain::io::shard {

/// 4: each patch one zstd-compressed payload (PatchPayload.h) in a deep part, its heights
/// possibly predicted from its parent's; 3 had the same payloads without that prediction and
/// with the block errors block by block; 2 stored the height codes, mask and block errors in
/// flat ZIP parts; 1 (pyramid versions 2 and 3) stored the heights as floats.
inline constexpr int kFormatVersion = 4;

inline constexpr const char* kPatchesPart = "patches";
inline constexpr const char* kPatchInfoPart = "patchInfo";
inline constexpr int kPatchesIndex = 0;  // part order as written; readers look parts up by name
inline constexpr int kPatchInfoIndex = 1;
inline constexpr int kPartCount = 2;

/// The one channel of the patches part: UINT samples, a patch's payload (PatchPayload.h).
inline constexpr const char* kPayloadChannel = "payload";

inline constexpr const char* kFormatVersionAttribute = "terrain:formatVersion";
inline constexpr const char* kLevelAttribute = "terrain:level";
inline constexpr const char* kShardAttribute = "terrain:shard";
/// The patches part's shape of its payloads (PatchPayload.h), so that a reader tells a shard
/// of another layout from a damaged one: tile samples N + 2, blocks per side, mask 0 or 1.
inline constexpr const char* kTileSamplesAttribute = "terrain:tileSamples";
inline constexpr const char* kBlocksPerSideAttribute = "terrain:blocksPerSide";
inline constexpr const char* kMaskAttribute = "terrain:mask";

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

/// The frame buffer of one pixel of the patches part, the pixel of the tile being read or
/// written (tile coordinates): its sample count in `count`, its samples at `samples` (the
/// frame buffer refers to both variables, which must outlive its use).
Imf::DeepFrameBuffer payloadFrame(unsigned int& count, char*& samples);

/// The two part headers of shard `s`, in part order. compressionLevel is the writer's
/// setting (not stored in the file): 0 stores the patchInfo tile uncompressed too.
std::vector<Imf::Header> shardHeaders(const PyramidLayout& layout, const ShardId& s, bool withMask,
                                      int compressionLevel);

/// Checks that `actual` (one part's header, found by name) has the structure of
/// `expected`: type, tiling, data window, channels and terrain attributes. The message
/// says what differs, without the file name.
Status checkPartHeader(const Imf::Header& actual, const Imf::Header& expected);

}  // namespace terrain::io::shard
