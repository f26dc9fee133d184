// PyramidReader: reads patches of a pyramid on disk (docs/pyramid-format.md) in O(1):
// the patch's shard path follows from its id, the shard's tile offset table gives the
// tile. Shards stay open in a small LRU so a streaming I/O thread does not reopen a file
// per tile.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/remote/RemoteStats.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>

namespace terrain::remote {
class RemoteRun;
}

namespace terrain::io {

class ParentTileCache;

/// One reader per thread: a reader and everything it returns belong to the thread that
/// uses it (it holds open files and scratch buffers). Several readers, one per thread,
/// may read the same pyramid at once. Move-only.
class PyramidReader {
public:
    /// Shard files kept open (least recently used closed first). Reopening one (headers,
    /// offset tables, the patchInfo tile) costs about as much as decoding two patches, and
    /// an open shard holds about 70 KB: 32 keep a shuffled read of a 16K pyramid's 89 shards
    /// above 2,500 patches a second (docs/pyramid-format.md, "Compression"), while the
    /// memory the two readers of a stress run may still add after its warm-up, as their
    /// LRUs fill, stays near 1 % (64: 3,400 a second, and a 16K stress run grew 0.9 %).
    static constexpr int kDefaultOpenShards = 32;

    /// Decoded heights of patches with children kept for their children (a patch's heights
    /// may be predicted from its parent's, docs/pyramid-format.md, "Height codes"), per
    /// reader thread: 4 MiB, 61 tiles of 129-sample patches (ParentTileCache.h).
    static constexpr std::size_t kParentCacheBytes = std::size_t{4} << 20;

    /// Reads and checks the manifest (readManifest), and a globe's native grids'; shard files
    /// are opened on demand. The
    /// virtual planet's name ("planet:…", VirtualPlanetPyramid.h) opens a reader that
    /// generates each patch instead of reading it (it has no shard files). `parents`: a
    /// cache of decoded parents shared with other readers of the same pyramid (each on its
    /// own thread); null: a cache of kParentCacheBytes of its own. `confirmed`: for a pyramid
    /// at a URL, the files this run's other readers have confirmed with the server, so that
    /// each is confirmed once (null: this reader's own).
    static Result<PyramidReader> open(const std::filesystem::path& pyramidDir,
                                      int maxOpenShards = kDefaultOpenShards,
                                      std::shared_ptr<ParentTileCache> parents = nullptr,
                                      std::shared_ptr<remote::RemoteRun> run = nullptr);

    PyramidReader(PyramidReader&& other) noexcept;
    PyramidReader& operator=(PyramidReader&& other) noexcept;
    PyramidReader(const PyramidReader&) = delete;
    PyramidReader& operator=(const PyramidReader&) = delete;
    ~PyramidReader();

    const std::filesystem::path& folder() const;
    const PyramidManifest& manifest() const;
    const PyramidLayout& layout() const;
    bool hasMask() const;  ///< the shards carry the V mask (manifest noData.present)

    /// Heights (+ mask), block errors and info of a present patch, its CRC-32 verified.
    /// Errors, each naming the shard file and the patch: outside the pyramid, absent
    /// (does not overlap the DEM), missing or corrupt/truncated shard, checksum mismatch.
    Result<PatchRecord> readPatch(const PatchId& id);

    /// The same into `out`, reusing its vectors' storage (no allocation once they have
    /// grown). On an Error `out` holds nothing useful.
    Status readPatch(const PatchId& id, PatchRecord& out);

    /// The patch's info only (from the shard's patchInfo tile, cached while the shard is
    /// open); absent patches are not an error here (present = false).
    Result<PatchInfo> patchInfo(const PatchId& id);

    /// Path of the shard file holding `id` (which must be contained).
    std::filesystem::path shardFile(const PatchId& id) const;
    /// The bytes of the shard file holding `id` (opened, and for a pyramid at a URL fetched,
    /// as a read would): what the shard costs on disk or on the wire.
    Result<std::uint64_t> shardBytes(const PatchId& id);

    /// What reading a pyramid at a URL has cost so far: requests, bytes fetched, disk cache
    /// hits (all zero for a folder).
    remote::RemoteStats remoteStats() const;

    int openShards() const;               ///< shards open now, ≤ maxOpenShards
    std::uint64_t shardOpenings() const;  ///< shard files opened so far (LRU misses)
    /// Parents read only to decode a child predicted from them (not among the patches
    /// kept for that), so far.
    std::uint64_t parentReads() const;
    /// The bytes of the patch payloads read so far, as stored (compressed) in their shard
    /// files, parents read for a prediction included: what the reads needed of the files,
    /// against which the bytes fetched (remoteStats) or the shard files' sizes are measured.
    std::uint64_t storedBytesRead() const;

    /// A globe pyramid's native grid of its source `k` (ManifestGlobeSource::native), opened
    /// with it; null where the source has none. readPatch, patchInfo, shardFile and shardBytes
    /// take its finest tiles by their native tile ids (NativeTiles.h), and the counters above
    /// include what its reads cost.
    const PyramidReader* nativeGrid(std::size_t k) const;

private:
    struct Impl;
    explicit PyramidReader(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

}  // namespace terrain::io
