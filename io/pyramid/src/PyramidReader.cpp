// Reading patches from a pyramid's shard files (docs/pyramid-format.md). Each open shard
// keeps its OpenEXR file, its deep patches part and its patchInfo tile; a least-recently-used
// list caps how many stay open. Everything OpenEXR throws becomes an Error naming the
// shard file and the patch, and the shard is closed so a damaged file is not reused.
#include "terrain/pyramid/PyramidReader.h"
#include "RemoteShardStream.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/pyramid/NativeTiles.h"
#include "terrain/pyramid/ParentTileCache.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"
#include "terrain/remote/RemoteFiles.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/ExrHeaderCheck.h"

#include "PatchChecksum.h"
#include "PatchPayload.h"
#include "ShardFormat.h"

#include <ImfDeepFrameBuffer.h>
#include <ImfDeepTiledInputPart.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartInputFile.h>
#include <ImfTiledInputPart.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <exception>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace terrain::io {
namespace {

std::string patchName(const PatchId& id) {
    return fmt::format("patch L{} ({}, {})", id.level, id.x, id.y);
}

struct OpenShard {
    ShardId id;
    std::filesystem::path path;   // named in messages (a URL for a remote pyramid)
    std::filesystem::path local;  // opened: path itself (empty for a pyramid at a URL)
    int countX = 0, countY = 0;
    // A pyramid at a URL: the shard read by ranges, and OpenEXR's stream over it (declared
    // before `file`, which reads through them, so that they outlive it).
    std::unique_ptr<remote::RemoteFile> remoteFile;
    std::unique_ptr<RemoteExrStream> remoteStream;
    std::unique_ptr<Imf::MultiPartInputFile> file;
    std::unique_ptr<Imf::DeepTiledInputPart> patches;
    // What the patches part's frame buffer reads into, set once when the shard is opened
    // (shard::payloadFrame): the pixel's sample count, then where its samples go.
    unsigned int payloadCount = 0;
    char* payloadSamples = nullptr;
    std::vector<shard::StoredInfo> infos;  // the patchInfo tile, row-major
    std::uint64_t lastUse = 0;
};

// Why a shard cannot be used, without the file name (the caller adds file and patch).
struct ShardProblem {
    std::string what;
};

}  // namespace

struct PyramidReader::Impl {
    std::filesystem::path folder;
    PyramidManifest manifest;
    PyramidLayout layout;
    bool hasMask = false;
    int maxOpen = kDefaultOpenShards;
    // A pyramid at a URL: where its shard files are fetched by ranges (issue 49); null for a
    // folder. Declared before `shards`, whose files read through it, so that it outlives them.
    std::unique_ptr<remote::RemoteFiles> remote;
    std::vector<std::unique_ptr<OpenShard>> shards;  // ≤ maxOpen, any order
    std::uint64_t clock = 0;
    std::uint64_t openings = 0;
    std::vector<std::uint32_t> payloadScratch;  // one patch's payload samples
    std::vector<std::uint32_t> codeScratch;     // its height codes
    std::vector<float> parentScratch;           // its parent samples (HeightCodes.h)
    std::shared_ptr<ParentTileCache> parents;   // maybe shared with other readers' threads
    std::uint64_t parentReads = 0;
    std::uint64_t storedBytesRead = 0;  // the payloads of the patches read
    // The virtual planet (VirtualPlanetPyramid.h): patches generated instead of read.
    std::optional<VirtualPlanetPyramid> planet;
    // A globe's native grids (NativeTiles.h), by source index: a reader of each planar
    // pyramid, on this reader's thread; null where a source has none.
    std::vector<std::unique_ptr<PyramidReader>> natives;

    // The native grid a native tile id names, and the tile's id in it (its finest level).
    Result<std::pair<PyramidReader*, PatchId>> native(const PatchId& id) {
        const auto k = static_cast<std::size_t>(nativeGridOf(id));
        if (k >= natives.size() || natives[k] == nullptr)
            return Error{fmt::format("{}: native tile {} ({}, {}): source {} has no native grid",
                                     folder.string(), k, id.x, id.y, k)};
        PyramidReader& grid = *natives[k];
        return std::pair(&grid, PatchId{grid.layout().finestLevel(), id.x, id.y});
    }

    // The heights of a patch's parent: from the cache, else read (and verified) now. The
    // parent's read reuses the scratch buffers, so the child's codes are kept apart meanwhile.
    Result<ParentTileCache::Heights> parentHeights(const PatchId& parent) {
        if (ParentTileCache::Heights cached = parents->find(parent)) return cached;
        std::vector<std::uint32_t> childCodes;
        childCodes.swap(codeScratch);
        PatchRecord record;
        Status read = this->read(parent, record);
        childCodes.swap(codeScratch);
        if (!read) return read.error();
        ++parentReads;
        // read() kept it, unless a reader sharing the cache has already evicted it.
        if (ParentTileCache::Heights kept = parents->find(parent)) return kept;
        return std::make_shared<const std::vector<float>>(std::move(record.heights));
    }

    std::filesystem::path shardFile(const ShardId& s) const { return folder / layout.shardPath(s); }

    Error patchError(const std::filesystem::path& file, const PatchId& id,
                     const std::string& what) const {
        return Error{fmt::format("{}: {}: {}", file.string(), patchName(id), what)};
    }

    // A globe pyramid is sparse: a shard it does not list has no file and no present patch.
    bool shardListed(const ShardId& s) const {
        if (!manifest.globe) return true;
        const std::vector<ShardId>& listed =
            manifest.levels[static_cast<std::size_t>(s.level)].presentShards;
        return std::binary_search(listed.begin(), listed.end(), s,
                                  [](const ShardId& a, const ShardId& b) {
                                      return std::pair(a.y, a.x) < std::pair(b.y, b.x);
                                  });
    }

    Status checkContains(const PatchId& id) const {
        if (id.level < 0 || id.level > layout.finestLevel())
            return Error{fmt::format("{}: {} is outside the pyramid (levels 0 to {})",
                                     folder.string(), patchName(id), layout.finestLevel())};
        if (!layout.contains(id))
            return Error{fmt::format("{}: {} is outside the pyramid (level {} has {} × {} patches)",
                                     folder.string(), patchName(id), id.level,
                                     layout.patchesX(id.level), layout.patchesY(id.level))};
        return {};
    }

    void close(const OpenShard* shard) {
        std::erase_if(shards, [&](const auto& s) { return s.get() == shard; });
    }

    // The open shard, opening it (and closing the least recently used) when needed.
    Result<OpenShard*> shard(const ShardId& s, const PatchId& forPatch) {
        ++clock;
        for (auto& open : shards) {
            if (open->id == s) {
                open->lastUse = clock;
                return open.get();
            }
        }
        const std::filesystem::path path = shardFile(s);
        Result<std::unique_ptr<OpenShard>> opened = openShard(s, path);
        if (!opened) return patchError(path, forPatch, opened.error().message);
        if (std::ssize(shards) >= maxOpen) {
            const auto oldest = std::min_element(
                shards.begin(), shards.end(),
                [](const auto& a, const auto& b) { return a->lastUse < b->lastUse; });
            shards.erase(oldest);
        }
        opened.value()->lastUse = clock;
        shards.push_back(std::move(opened).value());
        return shards.back().get();
    }

    // Error messages here are the "what" only; shard() adds the file and the patch.
    Result<std::unique_ptr<OpenShard>> openShard(const ShardId& s,
                                                 const std::filesystem::path& path) {
        auto shard = std::make_unique<OpenShard>();
        shard->id = s;
        shard->path = path;
        shard->countX = layout.shardCountX(s);
        shard->countY = layout.shardCountY(s);
        if (remote) {  // read by ranges; checked with the server on its first opening
            Result<std::unique_ptr<remote::RemoteFile>> file = remote->openRanged(path.string());
            if (!file) return Error{"cannot fetch the shard file: " + file.error().message};
            shard->remoteFile = std::move(file).value();
            shard->remoteStream = std::make_unique<RemoteExrStream>(*shard->remoteFile);
        } else {
            std::error_code ec;
            if (!std::filesystem::exists(path, ec)) return Error{"the shard file is missing"};
            shard->local = path;
        }
        ++openings;
        // OpenEXR allocates what a damaged header declares before it reads it.
        if (shard->remoteFile) {
            RemoteFileBuffer buffer(*shard->remoteFile);
            std::istream in(&buffer);
            if (Status header = checkExrHeaderSizes(in, shard->remoteFile->size()); !header)
                return header.error();
        } else if (Status header = checkExrHeaderSizes(path); !header) {
            return header.error();
        }
        try {
            // 0 threads: a reader decodes on its own thread (one reader per thread).
            shard->file = shard->remoteStream
                              ? std::make_unique<Imf::MultiPartInputFile>(*shard->remoteStream, 0)
                              : std::make_unique<Imf::MultiPartInputFile>(path.c_str(), 0);
            const std::vector<Imf::Header> expected = shard::shardHeaders(layout, s, hasMask, 1);
            int index[shard::kPartCount] = {-1, -1};
            for (int p = 0; p < shard->file->parts(); ++p) {
                const Imf::Header& h = shard->file->header(p);
                if (!h.hasName()) continue;
                for (int e = 0; e < shard::kPartCount; ++e)
                    if (h.name() == expected[static_cast<std::size_t>(e)].name()) index[e] = p;
            }
            for (int e = 0; e < shard::kPartCount; ++e) {
                const Imf::Header& want = expected[static_cast<std::size_t>(e)];
                if (index[e] < 0)
                    return Error{
                        fmt::format("not a shard of this pyramid: no part '{}'", want.name())};
                if (Status ok = shard::checkPartHeader(shard->file->header(index[e]), want); !ok)
                    return Error{"not a shard of this pyramid: " + ok.error().message};
            }
            shard->patches = std::make_unique<Imf::DeepTiledInputPart>(*shard->file,
                                                                       index[shard::kPatchesIndex]);
            shard->patches->setFrameBuffer(
                shard::payloadFrame(shard->payloadCount, shard->payloadSamples));
            if (Status read = readInfo(*shard, index[shard::kPatchInfoIndex]); !read)
                return read.error();
        } catch (const std::exception& e) {
            return Error{fmt::format("cannot read the shard file: {}", e.what())};
        }
        return shard;
    }

    Status readInfo(OpenShard& shard, int part) {
        Imf::TiledInputPart info(*shard.file, part);
        shard.infos.assign(
            static_cast<std::size_t>(shard.countX) * static_cast<std::size_t>(shard.countY),
            shard::StoredInfo{});
        char* base = reinterpret_cast<char*>(shard.infos.data());
        const std::size_t xs = sizeof(shard::StoredInfo);
        const std::size_t ys = xs * static_cast<std::size_t>(shard.countX);
        const auto slice = [&](Imf::PixelType type, std::size_t offset) {
            return Imf::Slice(type, base + offset, xs, ys);
        };
        Imf::FrameBuffer frame;
        frame.insert("present", slice(Imf::UINT, offsetof(shard::StoredInfo, present)));
        frame.insert("minHeight", slice(Imf::FLOAT, offsetof(shard::StoredInfo, minHeight)));
        frame.insert("maxHeight", slice(Imf::FLOAT, offsetof(shard::StoredInfo, maxHeight)));
        frame.insert("error", slice(Imf::FLOAT, offsetof(shard::StoredInfo, error)));
        frame.insert("approxError", slice(Imf::FLOAT, offsetof(shard::StoredInfo, approxError)));
        frame.insert("quantError", slice(Imf::FLOAT, offsetof(shard::StoredInfo, quantError)));
        frame.insert("noDataSamples", slice(Imf::UINT, offsetof(shard::StoredInfo, noDataSamples)));
        frame.insert("crc32", slice(Imf::UINT, offsetof(shard::StoredInfo, crc32)));
        frame.insert("heightDivisor", slice(Imf::UINT, offsetof(shard::StoredInfo, heightDivisor)));
        info.setFrameBuffer(frame);
        info.readTile(0, 0);
        // Absent patches are all zeros (their crc32 too), so a damaged present flag is
        // noticed here whichever way it flipped (1 → 0 here, 0 → 1 by the checksum).
        const shard::StoredInfo zero{};
        const std::uint32_t maxPresent =
            manifest.globe ? shard::kMaxStoredPresentGlobe : shard::kMaxStoredPresentPlanar;
        for (std::size_t i = 0; i < shard.infos.size(); ++i) {
            const shard::StoredInfo& p = shard.infos[i];
            const bool absentButNotZero =
                p.present == 0 && std::memcmp(&p, &zero, sizeof(shard::StoredInfo)) != 0;
            if (p.present > maxPresent || absentButNotZero)
                return Error{fmt::format(
                    "corrupt patchInfo: pixel ({}, {}) has present = {} and {} other fields",
                    i % static_cast<std::size_t>(shard.countX),
                    i / static_cast<std::size_t>(shard.countX), p.present,
                    absentButNotZero ? "non-zero" : "any")};
            const std::span<const std::uint32_t> divisors = heightDivisors();
            const bool quantizerSteps =
                p.heightDivisor == kQuantizerSteps && manifest.quantization.has_value();
            if (p.heightDivisor != 0 && p.heightDivisor != kSourceUnits && !quantizerSteps &&
                std::find(divisors.begin(), divisors.end(), p.heightDivisor) == divisors.end())
                return Error{fmt::format(
                    "corrupt patchInfo: pixel ({}, {}) has heightDivisor {}, not one a writer uses",
                    i % static_cast<std::size_t>(shard.countX),
                    i / static_cast<std::size_t>(shard.countX), p.heightDivisor)};
        }
        return {};
    }

    static std::size_t infoIndex(const OpenShard& shard, const PyramidLayout& layout,
                                 const PatchId& id) {
        const std::int64_t tx = id.x - layout.shardFirstX(shard.id);
        const std::int64_t ty = id.y - layout.shardFirstY(shard.id);
        return static_cast<std::size_t>(ty * shard.countX + tx);
    }

    Status read(const PatchId& id, PatchRecord& out) {
        if (Status inside = checkContains(id); !inside) return inside;
        if (planet) return planet->generate(id, out);
        if (!shardListed(layout.shardOf(id)))
            return patchError(shardFile(layout.shardOf(id)), id,
                              "the patch is absent (the globe pyramid has no data there)");
        Result<OpenShard*> opened = shard(layout.shardOf(id), id);
        if (!opened) return opened.error();
        OpenShard& s = *opened.value();
        const shard::StoredInfo& stored = s.infos[infoIndex(s, layout, id)];
        if (stored.present == 0)
            return patchError(s.path, id, "the patch is absent (it does not overlap the DEM)");

        const shard::PayloadShape shape{layout.tileSamples(), layout.blocksPerSide(), hasMask};
        out.id = id;
        out.info = shard::fromStored(stored);
        const int tx = static_cast<int>(id.x - layout.shardFirstX(s.id));
        const int ty = static_cast<int>(id.y - layout.shardFirstY(s.id));
        try {
            s.patches->readPixelSampleCounts(tx, tx, ty, ty);
            // Checked before anything is allocated for it: the count is the file's word.
            if (s.payloadCount > shard::maxPayloadWords(shape))
                return patchError(s.path, id,
                                  fmt::format("its payload claims {} samples, more than a patch "
                                              "can take ({}): the shard is corrupt",
                                              s.payloadCount, shard::maxPayloadWords(shape)));
            payloadScratch.resize(s.payloadCount);
            s.payloadSamples = reinterpret_cast<char*>(payloadScratch.data());
            s.patches->readTile(tx, ty);
            storedBytesRead += std::uint64_t{s.payloadCount} * sizeof(std::uint32_t);
        } catch (const std::exception& e) {
            const std::filesystem::path path = s.path;
            close(&s);  // a shard that failed once is reopened (and rechecked) next time
            return patchError(path, id, fmt::format("cannot read its tile: {}", e.what()));
        }
        HeightEncoding encoding{stored.heightDivisor, HeightPrediction::kWithinTile};
        if (Status unpacked =
                shard::unpackPatchPayload(payloadScratch, shape, codeScratch, encoding.prediction,
                                          out.valid, out.blockErrors);
            !unpacked)
            return patchError(s.path, id, unpacked.error().message + ": the shard is corrupt");
        // `s` may be closed from here on: reading the parent can open other shards.
        const std::filesystem::path path = s.path;
        const std::uint32_t storedCrc = stored.crc32;
        const bool fromParent = encoding.prediction != HeightPrediction::kWithinTile;
        if (fromParent) {
            if (id.level == 0 || manifest.globe)
                return patchError(path, id,
                                  "its heights are predicted from a parent patch it does not "
                                  "have: the shard is corrupt");
            Result<ParentTileCache::Heights> parent =
                parentHeights(PatchId{id.level - 1, id.x / 2, id.y / 2});
            if (!parent)
                return patchError(path, id,
                                  "its heights are predicted from its parent's, which cannot be "
                                  "read: " +
                                      parent.error().message);
            gatherParentSamples(*parent.value(), shape.tileSamples, static_cast<int>(id.x % 2),
                                static_cast<int>(id.y % 2), parentScratch);
        }
        out.heights.resize(codeScratch.size());
        HeightUnits units{manifest.vertical};
        if (manifest.quantization)
            units.quantizerStep = manifest.quantization->step(id.level, layout.finestLevel());
        decodeHeights(
            codeScratch, shape.tileSamples, encoding, out.heights, units,
            fromParent ? std::span<const float>(parentScratch) : std::span<const float>());
        const std::uint32_t computed =
            patchChecksum(out.heights, out.valid, out.blockErrors, out.info);
        if (computed != storedCrc)
            return patchError(path, id,
                              fmt::format("checksum mismatch (stored 0x{:08x}, computed 0x{:08x})",
                                          storedCrc, computed));
        if (id.level < layout.finestLevel() && !manifest.globe) parents->insert(id, out.heights);
        return {};
    }
};

PyramidReader::PyramidReader(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
PyramidReader::PyramidReader(PyramidReader&& other) noexcept = default;
PyramidReader& PyramidReader::operator=(PyramidReader&& other) noexcept = default;
PyramidReader::~PyramidReader() = default;

Result<PyramidReader> PyramidReader::open(const std::filesystem::path& pyramidDir,
                                          int maxOpenShards,
                                          std::shared_ptr<ParentTileCache> parents,
                                          std::shared_ptr<remote::RemoteRun> run) {
    TERRAIN_ASSERT(maxOpenShards >= 1, "a reader keeps at least one shard open");
    if (isVirtualPlanetName(pyramidDir)) {
        Result<VirtualPlanetPyramid> planet = VirtualPlanetPyramid::open(pyramidDir);
        if (!planet) return planet.error();
        auto impl = std::make_unique<Impl>();
        impl->folder = pyramidDir;
        impl->manifest = planet.value().manifest();
        impl->layout = impl->manifest.layout;
        impl->planet = std::move(planet).value();
        return PyramidReader(std::move(impl));
    }
    Result<std::unique_ptr<remote::RemoteFiles>> files =
        remote::filesFor(pyramidDir.string(), run);  // the native grids share it
    if (!files) return files.error();
    Result<PyramidManifest> manifest = readManifest(pyramidDir, files.value().get());
    if (!manifest) return manifest.error();
    auto impl = std::make_unique<Impl>();
    impl->remote = std::move(files).value();
    impl->folder = pyramidDir;
    impl->manifest = std::move(manifest).value();
    impl->layout = impl->manifest.layout;
    impl->hasMask = impl->manifest.noData.present;
    impl->maxOpen = maxOpenShards;
    impl->parents =
        parents ? std::move(parents) : std::make_shared<ParentTileCache>(kParentCacheBytes);
    // A globe's native grids, read by this reader's thread through readers of their own.
    Result<std::vector<NativeGridManifest>> grids =
        readNativeGridManifests(pyramidDir, impl->manifest);
    if (!grids) return grids.error();
    for (const NativeGridManifest& grid : grids.value()) {
        const std::string& folder =
            impl->manifest.globe->sources[static_cast<std::size_t>(grid.source)].native;
        Result<PyramidReader> opened = open(pyramidDir / folder, maxOpenShards, nullptr, run);
        if (!opened) return opened.error();
        impl->natives.resize(impl->manifest.globe->sources.size());
        impl->natives[static_cast<std::size_t>(grid.source)] =
            std::make_unique<PyramidReader>(std::move(opened).value());
    }
    return PyramidReader(std::move(impl));
}

const std::filesystem::path& PyramidReader::folder() const { return m_impl->folder; }
const PyramidManifest& PyramidReader::manifest() const { return m_impl->manifest; }
const PyramidLayout& PyramidReader::layout() const { return m_impl->layout; }
bool PyramidReader::hasMask() const { return m_impl->hasMask; }

Result<PatchRecord> PyramidReader::readPatch(const PatchId& id) {
    PatchRecord record;
    if (Status read = readPatch(id, record); !read) return read.error();
    return record;
}

Status PyramidReader::readPatch(const PatchId& id, PatchRecord& out) {
    if (isNativeTile(id)) {
        auto native = m_impl->native(id);
        if (!native) return native.error();
        if (Status read = native.value().first->readPatch(native.value().second, out); !read)
            return read;
        out.id = id;
        return {};
    }
    return m_impl->read(id, out);
}

Result<PatchInfo> PyramidReader::patchInfo(const PatchId& id) {
    Impl& r = *m_impl;
    if (isNativeTile(id)) {
        auto native = r.native(id);
        if (!native) return native.error();
        return native.value().first->patchInfo(native.value().second);
    }
    if (Status inside = r.checkContains(id); !inside) return inside.error();
    if (r.planet) {
        if (id.level < ManifestGlobe::kLevelOffset) return PatchInfo{};
        return r.planet->info(id);
    }
    if (!r.shardListed(r.layout.shardOf(id))) return PatchInfo{};
    Result<OpenShard*> opened = r.shard(r.layout.shardOf(id), id);
    if (!opened) return opened.error();
    const OpenShard& s = *opened.value();
    return shard::fromStored(s.infos[Impl::infoIndex(s, r.layout, id)]);
}

std::filesystem::path PyramidReader::shardFile(const PatchId& id) const {
    if (isNativeTile(id)) {
        const auto k = static_cast<std::size_t>(nativeGridOf(id));
        if (k < m_impl->natives.size() && m_impl->natives[k] != nullptr) {
            const PyramidReader& grid = *m_impl->natives[k];
            return grid.shardFile({grid.layout().finestLevel(), id.x, id.y});
        }
        return m_impl->folder;
    }
    return m_impl->shardFile(m_impl->layout.shardOf(id));
}

Result<std::uint64_t> PyramidReader::shardBytes(const PatchId& id) {
    Impl& r = *m_impl;
    if (isNativeTile(id)) {
        auto native = r.native(id);
        if (!native) return native.error();
        return native.value().first->shardBytes(native.value().second);
    }
    if (Status inside = r.checkContains(id); !inside) return inside.error();
    if (r.planet) return std::uint64_t{0};  // generated, not stored
    Result<OpenShard*> opened = r.shard(r.layout.shardOf(id), id);
    if (!opened) return opened.error();
    if (opened.value()->remoteFile) return opened.value()->remoteFile->size();
    std::error_code ec;
    const std::uintmax_t bytes = std::filesystem::file_size(opened.value()->local, ec);
    if (ec) return Error{fmt::format("{}: {}", opened.value()->path.string(), ec.message())};
    return std::uint64_t{bytes};
}

// What the native grids' readers did counts as this reader's: they read for it.
remote::RemoteStats PyramidReader::remoteStats() const {
    remote::RemoteStats stats = m_impl->remote ? m_impl->remote->stats() : remote::RemoteStats{};
    for (const auto& grid : m_impl->natives)
        if (grid) stats += grid->remoteStats();
    return stats;
}
int PyramidReader::openShards() const {
    int open = static_cast<int>(m_impl->shards.size());
    for (const auto& grid : m_impl->natives)
        if (grid) open += grid->openShards();
    return open;
}
std::uint64_t PyramidReader::shardOpenings() const {
    std::uint64_t openings = m_impl->openings;
    for (const auto& grid : m_impl->natives)
        if (grid) openings += grid->shardOpenings();
    return openings;
}
std::uint64_t PyramidReader::parentReads() const {
    std::uint64_t reads = m_impl->parentReads;
    for (const auto& grid : m_impl->natives)
        if (grid) reads += grid->parentReads();
    return reads;
}
std::uint64_t PyramidReader::storedBytesRead() const {
    std::uint64_t bytes = m_impl->storedBytesRead;
    for (const auto& grid : m_impl->natives)
        if (grid) bytes += grid->storedBytesRead();
    return bytes;
}
/// The native grid of source `k` (NativeTiles.h), or null where it has none.
const PyramidReader* PyramidReader::nativeGrid(std::size_t k) const {
    return k < m_impl->natives.size() ? m_impl->natives[k].get() : nullptr;
}

}  // namespace terrain::io
