// Writing one shard file (docs/pyramid-format.md, "Shard files"). Patches are staged in
// per-row buffers laid out like the row of tiles they form, so a completed row goes to
// OpenEXR as one writeTiles() call that its worker pool compresses in parallel; the row
// buffers are reused, so nothing is allocated per patch once the first rows exist.
#include "terrain/io/ShardWriter.h"

#include "ExrFileStream.h"
#include "PatchChecksum.h"
#include "ShardFormat.h"
#include "terrain/base/AtomicFile.h"
#include "terrain/io/HeightCodes.h"
#include "terrain/io/PatchErrors.h"

#include <ImfFrameBuffer.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfThreading.h>
#include <ImfTiledOutputPart.h>
#include <fmt/format.h>
#include <half.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <exception>
#include <optional>
#include <thread>

namespace terrain::io {
namespace {

std::atomic<bool> g_threadsConfigured{false};

void configureDefaultThreads() {
    if (g_threadsConfigured.exchange(true)) return;
    Imf::setGlobalThreadCount(static_cast<int>(std::max(1U, std::thread::hardware_concurrency())));
}

// λ(1..4) of a block as the HALF bits OpenEXR writes (it converts halves to floats on
// reading, not floats to halves on writing).
using HalfBlockErrors = std::array<std::uint16_t, kMaxSimplification>;

// The staged samples of one row of the shard's tiles, in the layout of that row: sample
// (i, j) of tile tx is at [j · rowWidth + tx · tile + i]. Frame buffers use y relative to
// the tile (yTileCoords) so the same buffer serves any row.
struct RowBuffer {
    std::vector<std::uint32_t> heights;        // height codes
    std::vector<std::uint16_t> mask;           // HALF bits
    std::vector<HalfBlockErrors> blockErrors;  // [j · cx·K + tx · K + i]
};

}  // namespace

struct ShardWriter::Impl {
    PyramidLayout layout;
    ShardId shard;
    bool withMask = false;
    int cx = 0, cy = 0, tile = 0, blocks = 0;

    std::optional<AtomicFile> file;
    std::unique_ptr<ExrFileStream> stream;
    std::unique_ptr<Imf::MultiPartOutputFile> exr;
    std::unique_ptr<Imf::TiledOutputPart> heightsPart, blockErrorsPart, infoPart;

    std::vector<RowBuffer> rowPool;          // buffers, reused
    std::vector<int> freeRows;               // indices into rowPool
    std::vector<int> rowSlot;                // per tile row: index into rowPool, or −1
    std::vector<int> rowWritten;             // per tile row: patches staged
    std::vector<bool> rowDone;               // per tile row: tiles handed to OpenEXR
    std::vector<std::uint8_t> patchWritten;  // per patch of the shard
    std::vector<shard::StoredInfo> infos;    // the patchInfo tile
    std::vector<std::uint32_t> codes;        // one patch's height codes
    std::vector<BlockErrors> lambdas;        // its block errors, rounded up to halves
    HeightUnits units;
    Imf::FrameBuffer heightsFrame, blockErrorsFrame;

    std::optional<Error> failure;
    bool finished = false;

    std::string name() const { return file->path().string(); }

    Status fail(std::string message) {
        failure = Error{std::move(message)};
        return *failure;
    }

    // Turns what OpenEXR threw into an Error naming the file. The stream's own record of
    // an I/O error is the more precise message (errno) when there is one.
    Status failFromException(const char* what) {
        if (stream && !stream->firstError().empty()) return fail(stream->firstError());
        return fail(fmt::format("{}: cannot write the shard: {}", name(), what));
    }

    int acquireRow(int ty) {
        if (rowSlot[static_cast<std::size_t>(ty)] >= 0)
            return rowSlot[static_cast<std::size_t>(ty)];
        int slot = 0;
        if (!freeRows.empty()) {
            slot = freeRows.back();
            freeRows.pop_back();
        } else {
            slot = static_cast<int>(rowPool.size());
            RowBuffer& row = rowPool.emplace_back();
            const auto rowWidth = static_cast<std::size_t>(cx) * static_cast<std::size_t>(tile);
            row.heights.resize(rowWidth * static_cast<std::size_t>(tile));
            if (withMask) row.mask.resize(row.heights.size());
            row.blockErrors.resize(static_cast<std::size_t>(cx) * static_cast<std::size_t>(blocks) *
                                   static_cast<std::size_t>(blocks));
        }
        rowSlot[static_cast<std::size_t>(ty)] = slot;
        return slot;
    }

    // Stages the patch's height codes (in `codes`, tile² of them) and the rest of it.
    void stage(RowBuffer& row, int tx, const PatchRecord& record) {
        const auto t = static_cast<std::size_t>(tile);
        const std::size_t rowWidth = static_cast<std::size_t>(cx) * t;
        const std::size_t x0 = static_cast<std::size_t>(tx) * t;
        for (std::size_t j = 0; j < t; ++j) {
            std::copy_n(&codes[j * t], t, &row.heights[j * rowWidth + x0]);
            if (withMask) {
                std::uint16_t* out = &row.mask[j * rowWidth + x0];
                const std::uint8_t* in = &record.valid[j * t];
                for (std::size_t i = 0; i < t; ++i)
                    out[i] = in[i] != 0 ? shard::kHalfOne : shard::kHalfZero;
            }
        }
        const auto k = static_cast<std::size_t>(blocks);
        const std::size_t errorsWidth = static_cast<std::size_t>(cx) * k;
        for (std::size_t j = 0; j < k; ++j)
            for (std::size_t i = 0; i < k; ++i)
                for (std::size_t d = 0; d < kMaxSimplification; ++d)
                    row.blockErrors[j * errorsWidth + static_cast<std::size_t>(tx) * k + i][d] =
                        Imath::half(lambdas[j * k + i][d]).bits();  // exact: already a half
    }

    void stageZeros(RowBuffer& row, int tx) {
        const auto t = static_cast<std::size_t>(tile);
        const std::size_t rowWidth = static_cast<std::size_t>(cx) * t;
        const std::size_t x0 = static_cast<std::size_t>(tx) * t;
        for (std::size_t j = 0; j < t; ++j) {
            std::fill_n(&row.heights[j * rowWidth + x0], t, 0U);
            if (withMask) std::fill_n(&row.mask[j * rowWidth + x0], t, shard::kHalfZero);
        }
        const auto k = static_cast<std::size_t>(blocks);
        const std::size_t errorsWidth = static_cast<std::size_t>(cx) * k;
        for (std::size_t j = 0; j < k; ++j)
            std::fill_n(&row.blockErrors[j * errorsWidth + static_cast<std::size_t>(tx) * k], k,
                        HalfBlockErrors{});
    }

    // Hands tile row ty to OpenEXR (compressed in parallel) and recycles its buffer.
    Status writeRow(int ty) {
        const int slot = rowSlot[static_cast<std::size_t>(ty)];
        RowBuffer& row = rowPool[static_cast<std::size_t>(slot)];
        const std::size_t rowWidth = static_cast<std::size_t>(cx) * static_cast<std::size_t>(tile);
        const std::size_t errorsWidth =
            static_cast<std::size_t>(cx) * static_cast<std::size_t>(blocks);
        try {
            heightsFrame = Imf::FrameBuffer();
            shard::insertHeightCodeSlices(heightsFrame, row.heights.data(), rowWidth, false);
            if (withMask)
                heightsFrame.insert(
                    shard::kMaskChannel,
                    Imf::Slice(Imf::HALF, reinterpret_cast<char*>(row.mask.data()),
                               sizeof(std::uint16_t), sizeof(std::uint16_t) * rowWidth, 1, 1, 0.0,
                               false, true));
            heightsPart->setFrameBuffer(heightsFrame);
            heightsPart->writeTiles(0, cx - 1, ty, ty);

            blockErrorsFrame = Imf::FrameBuffer();
            for (std::size_t d = 0; d < kMaxSimplification; ++d)
                blockErrorsFrame.insert(
                    shard::kBlockErrorChannels[d],
                    Imf::Slice(Imf::HALF, reinterpret_cast<char*>(&row.blockErrors[0][d]),
                               sizeof(HalfBlockErrors), sizeof(HalfBlockErrors) * errorsWidth, 1, 1,
                               0.0, false, true));
            blockErrorsPart->setFrameBuffer(blockErrorsFrame);
            blockErrorsPart->writeTiles(0, cx - 1, ty, ty);
        } catch (const std::exception& e) {
            return failFromException(e.what());
        }
        rowDone[static_cast<std::size_t>(ty)] = true;
        rowSlot[static_cast<std::size_t>(ty)] = -1;
        freeRows.push_back(slot);
        return {};
    }

    Status writeInfo() {
        try {
            Imf::FrameBuffer frame;
            char* base = reinterpret_cast<char*>(infos.data());
            const std::size_t xs = sizeof(shard::StoredInfo);
            const std::size_t ys = xs * static_cast<std::size_t>(cx);
            const auto slice = [&](Imf::PixelType type, std::size_t offset) {
                return Imf::Slice(type, base + offset, xs, ys);
            };
            frame.insert("present", slice(Imf::UINT, offsetof(shard::StoredInfo, present)));
            frame.insert("minHeight", slice(Imf::FLOAT, offsetof(shard::StoredInfo, minHeight)));
            frame.insert("maxHeight", slice(Imf::FLOAT, offsetof(shard::StoredInfo, maxHeight)));
            frame.insert("error", slice(Imf::FLOAT, offsetof(shard::StoredInfo, error)));
            frame.insert("approxError",
                         slice(Imf::FLOAT, offsetof(shard::StoredInfo, approxError)));
            frame.insert("quantError", slice(Imf::FLOAT, offsetof(shard::StoredInfo, quantError)));
            frame.insert("noDataSamples",
                         slice(Imf::UINT, offsetof(shard::StoredInfo, noDataSamples)));
            frame.insert("crc32", slice(Imf::UINT, offsetof(shard::StoredInfo, crc32)));
            frame.insert("heightDivisor",
                         slice(Imf::UINT, offsetof(shard::StoredInfo, heightDivisor)));
            infoPart->setFrameBuffer(frame);
            infoPart->writeTile(0, 0);
        } catch (const std::exception& e) {
            return failFromException(e.what());
        }
        return {};
    }

    // Destroys the OpenEXR objects (which write the offset tables) and closes the file.
    Status closeFile() {
        try {
            heightsPart.reset();
            blockErrorsPart.reset();
            infoPart.reset();
            exr.reset();
        } catch (const std::exception& e) {
            return failFromException(e.what());
        }
        if (Status closed = stream->close(); !closed) return fail(closed.error().message);
        return {};
    }
};

ShardWriter::ShardWriter(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
ShardWriter::ShardWriter(ShardWriter&& other) noexcept = default;
ShardWriter& ShardWriter::operator=(ShardWriter&& other) noexcept = default;

// Unfinished, Impl's members go in reverse order: the OpenEXR parts and file (their
// destructors swallow errors), the stream (closes without flushing), then the AtomicFile,
// which removes the temporary file.
ShardWriter::~ShardWriter() = default;

void ShardWriter::setCompressionThreads(int threads) {
    g_threadsConfigured = true;
    Imf::setGlobalThreadCount(std::max(0, threads));
}

const std::filesystem::path& ShardWriter::path() const { return m_impl->file->path(); }
const ShardId& ShardWriter::shard() const { return m_impl->shard; }

Result<ShardWriter> ShardWriter::create(const std::filesystem::path& finalPath,
                                        const PyramidLayout& layout, const ShardId& shardId,
                                        bool withMask, const ShardWriterOptions& options) {
    TERRAIN_ASSERT(layout.contains(shardId), "shard outside the pyramid");
    if (options.zipLevel < 0 || options.zipLevel > 9)
        return Error{fmt::format("{}: ZIP level {}: must be from 0 (uncompressed) to 9",
                                 finalPath.string(), options.zipLevel)};
    configureDefaultThreads();

    std::error_code ec;
    if (finalPath.has_parent_path()) {
        std::filesystem::create_directories(finalPath.parent_path(), ec);
        if (ec)
            return Error{fmt::format("{}: cannot create folder '{}': {}", finalPath.string(),
                                     finalPath.parent_path().string(), ec.message())};
    }
    Result<AtomicFile> file = AtomicFile::create(finalPath);
    if (!file) return file.error();

    auto impl = std::make_unique<Impl>();
    impl->layout = layout;
    impl->shard = shardId;
    impl->withMask = withMask;
    impl->units = options.units;
    impl->cx = layout.shardCountX(shardId);
    impl->cy = layout.shardCountY(shardId);
    impl->tile = layout.tileSamples();
    impl->blocks = layout.blocksPerSide();
    impl->file.emplace(std::move(file).value());
    const auto patches = static_cast<std::size_t>(impl->cx) * static_cast<std::size_t>(impl->cy);
    impl->rowSlot.assign(static_cast<std::size_t>(impl->cy), -1);
    impl->rowWritten.assign(static_cast<std::size_t>(impl->cy), 0);
    impl->rowDone.assign(static_cast<std::size_t>(impl->cy), false);
    impl->patchWritten.assign(patches, 0);
    impl->infos.assign(patches, shard::StoredInfo{});

    Result<std::unique_ptr<ExrFileStream>> stream =
        ExrFileStream::open(impl->file->temporaryPath(), finalPath.string());
    if (!stream) return stream.error();
    impl->stream = std::move(stream).value();
    try {
        const std::vector<Imf::Header> headers =
            shard::shardHeaders(layout, shardId, withMask, options.zipLevel);
        impl->exr = std::make_unique<Imf::MultiPartOutputFile>(*impl->stream, headers.data(),
                                                               static_cast<int>(headers.size()));
        impl->heightsPart =
            std::make_unique<Imf::TiledOutputPart>(*impl->exr, shard::kHeightsIndex);
        impl->blockErrorsPart =
            std::make_unique<Imf::TiledOutputPart>(*impl->exr, shard::kBlockErrorsIndex);
        impl->infoPart = std::make_unique<Imf::TiledOutputPart>(*impl->exr, shard::kPatchInfoIndex);
    } catch (const std::exception& e) {
        return impl->failFromException(e.what()).error();
    }
    return ShardWriter(std::move(impl));
}

Status ShardWriter::writePatch(const PatchRecord& record) {
    Impl& w = *m_impl;
    if (w.failure) return *w.failure;
    TERRAIN_ASSERT(!w.finished, "ShardWriter::writePatch after finish()");
    const PyramidLayout& layout = w.layout;
    TERRAIN_ASSERT(layout.contains(record.id) && layout.shardOf(record.id) == w.shard,
                   "patch outside this shard");
    const auto tile2 = static_cast<std::size_t>(w.tile) * static_cast<std::size_t>(w.tile);
    TERRAIN_ASSERT(record.heights.size() == tile2, "heights must hold tileSamples² values");
    TERRAIN_ASSERT(record.valid.size() == (w.withMask ? tile2 : 0),
                   "valid must hold tileSamples² values with a mask, none without");
    TERRAIN_ASSERT(record.blockErrors.size() ==
                       static_cast<std::size_t>(w.blocks) * static_cast<std::size_t>(w.blocks),
                   "blockErrors must hold blocksPerSide² entries");
    TERRAIN_ASSERT(record.info.present, "only present patches are written");
    const auto tx = static_cast<int>(record.id.x - layout.shardFirstX(w.shard));
    const auto ty = static_cast<int>(record.id.y - layout.shardFirstY(w.shard));
    const std::size_t index = static_cast<std::size_t>(ty) * static_cast<std::size_t>(w.cx) +
                              static_cast<std::size_t>(tx);
    TERRAIN_ASSERT(w.patchWritten[index] == 0, "patch written twice");

    PatchInfo info = record.info;
    // The block errors as stored: rounded up to halves, and checksummed so.
    w.lambdas.resize(record.blockErrors.size());
    for (std::size_t b = 0; b < record.blockErrors.size(); ++b)
        for (std::size_t d = 0; d < kMaxSimplification; ++d)
            w.lambdas[b][d] = roundUpToHalf(record.blockErrors[b][d]);
    info.crc32 = patchChecksum(record.heights, record.valid, w.lambdas, info);
    w.codes.resize(tile2);
    const std::uint32_t divisor = encodeHeights(record.heights, w.tile, w.codes, w.units);
    w.infos[index] = shard::toStored(info, divisor);
    w.patchWritten[index] = 1;
    const int slot = w.acquireRow(ty);
    w.stage(w.rowPool[static_cast<std::size_t>(slot)], tx, record);
    if (++w.rowWritten[static_cast<std::size_t>(ty)] == w.cx) return w.writeRow(ty);
    return {};
}

Status ShardWriter::finish() {
    Impl& w = *m_impl;
    if (w.failure) return *w.failure;
    TERRAIN_ASSERT(!w.finished, "ShardWriter::finish() called twice");
    w.finished = true;
    for (int ty = 0; ty < w.cy; ++ty) {
        if (w.rowDone[static_cast<std::size_t>(ty)]) continue;
        RowBuffer& row = w.rowPool[static_cast<std::size_t>(w.acquireRow(ty))];
        for (int tx = 0; tx < w.cx; ++tx)
            if (w.patchWritten[static_cast<std::size_t>(ty * w.cx + tx)] == 0)
                w.stageZeros(row, tx);
        if (Status written = w.writeRow(ty); !written) return written;
    }
    if (Status written = w.writeInfo(); !written) return written;
    if (Status closed = w.closeFile(); !closed) return closed;
    if (Status committed = w.file->commit(); !committed) return w.fail(committed.error().message);
    return {};
}

}  // namespace terrain::io
