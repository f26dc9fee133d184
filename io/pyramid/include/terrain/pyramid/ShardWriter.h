// ShardWriter: writes one shard of the pyramid, the patches (l, px, py) of one S × S block
// of a level, as the multi-part OpenEXR file docs/pyramid-format.md describes, under a
// temporary name that finish() renames into place.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"

#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace terrain::io {

struct ShardWriterOptions {
    /// zstd level of the patch payloads: 1 fastest … 19 smallest, lossless at every level
    /// (docs/pyramid-format.md, "Compression"); 0 stores them uncompressed. Level 3, zstd's
    /// own default, compresses the shared DEMs' payloads at 240–830 MB/s on one core, as
    /// small as zlib's level 4 does at 60–270 MB/s.
    static constexpr int kDefaultCompressionLevel = 3;
    int compressionLevel = kDefaultCompressionLevel;
    /// The manifest's vertical transform and, in a lossy pyramid, the shard's level's
    /// quantizer step: the units the height codes may count in (HeightCodes.h).
    HeightUnits units;
};

/// One patch coded, packed and compressed as a shard stores it: what ShardWriter::writePatch
/// makes before it writes. Making it is most of a write's cost (the height codes' search for
/// their prediction and divisor, zstd), so a builder makes a band's patches on all its
/// threads (encodePatch) and its writer only copies them into the file (writeEncoded).
struct EncodedPatch {
    PatchId id;
    PatchInfo info;  ///< with its crc32 set
    std::uint32_t heightDivisor = 0;
    std::vector<std::uint32_t> payload;  ///< the deep pixel's 32-bit samples
};

/// Codes, packs and compresses `record` exactly as ShardWriter::writePatch does for a shard
/// of `layout` opened with `withMask` and `options` (same preconditions, asserted, but for
/// the shard's own ones), into `out`, whose storage is reused. Any thread: its scratch is
/// per thread.
void encodePatch(const PatchRecord& record, std::span<const float> parentSamples,
                 const PyramidLayout& layout, bool withMask, const ShardWriterOptions& options,
                 EncodedPatch& out);

/// Writes one shard. Move-only; used by one thread at a time (its owner), which also
/// compresses each patch as it is written (writePatch), unless it was encoded before
/// (encodePatch, writeEncoded). Destroying a writer before finish()
/// succeeded removes its temporary file; nothing appears at the final path.
class ShardWriter {
public:
    /// Creates the final path's folders and the temporary file beside it, and writes the
    /// file's headers. `withMask`: the payloads carry the no-data mask (the pyramid has
    /// no-data). Errors name `finalPath`.
    static Result<ShardWriter> create(const std::filesystem::path& finalPath,
                                      const PyramidLayout& layout, const ShardId& shard,
                                      bool withMask, const ShardWriterOptions& options = {});

    ShardWriter(ShardWriter&& other) noexcept;
    ShardWriter& operator=(ShardWriter&& other) noexcept;
    ShardWriter(const ShardWriter&) = delete;
    ShardWriter& operator=(const ShardWriter&) = delete;
    ~ShardWriter();

    /// Stores one present patch of this shard, in any order, each patch at most once.
    /// Computes record.info.crc32 (the value passed in is ignored) from the heights, mask
    /// and block errors as the spec defines it. Preconditions (asserted): the patch lies
    /// in this shard and was not written before, info.present, heights has
    /// tileSamples² values, valid tileSamples² (withMask) or none, blockErrors
    /// blocksPerSide². `parentSamples` (HeightCodes.h; empty: none, as at the root and in a
    /// globe pyramid) must be exactly the heights the parent patch is stored with, at this
    /// patch's odd sample indices: the reader predicts from the parent it reads. An I/O
    /// error (e.g. a full disk) is an Error naming the file; after one, every later call
    /// returns it again.
    Status writePatch(const PatchRecord& record, std::span<const float> parentSamples = {});

    /// Stores a patch encodePatch made with this shard's layout, mask and options: the same
    /// bytes writePatch(record, parentSamples) writes. Same preconditions on the patch's
    /// place (in this shard, once) and the same errors.
    Status writeEncoded(const EncodedPatch& patch);

    /// Writes empty payloads (present = 0) for the patches never written, the patchInfo
    /// tile, closes the file and renames it into place. Call once.
    Status finish();

    const std::filesystem::path& path() const;  ///< the final path
    const ShardId& shard() const;

private:
    struct Impl;
    explicit ShardWriter(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

}  // namespace terrain::io
