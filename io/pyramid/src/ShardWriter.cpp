// Writing one shard file (docs/pyramid-format.md, "Shard files"). Each patch is coded,
// packed and compressed (PatchPayload.h) as it arrives and written at once as one deep
// pixel; OpenEXR only copies it, so nothing is staged beyond the patch at hand.
#include "terrain/pyramid/ShardWriter.h"

#include "ExrFileStream.h"
#include "PatchChecksum.h"
#include "PatchPayload.h"
#include "ShardFormat.h"
#include "terrain/base/AtomicFile.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/pyramid/PatchErrors.h"

#include <ImfDeepFrameBuffer.h>
#include <ImfDeepTiledOutputPart.h>
#include <ImfFrameBuffer.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfTiledOutputPart.h>
#include <fmt/format.h>
#include <half.h>

#include <algorithm>
#include <cstddef>
#include <exception>
#include <optional>

namespace terrain::io {

struct ShardWriter::Impl {
    PyramidLayout layout;
    ShardId shard;
    bool withMask = false;
    int compressionLevel = 0;
    int cx = 0, cy = 0, tile = 0, blocks = 0;

    std::optional<AtomicFile> file;
    std::unique_ptr<ExrFileStream> stream;
    std::unique_ptr<Imf::MultiPartOutputFile> exr;
    std::unique_ptr<Imf::DeepTiledOutputPart> patchesPart;
    std::unique_ptr<Imf::TiledOutputPart> infoPart;

    std::vector<std::uint8_t> patchWritten;  // per patch of the shard
    std::vector<shard::StoredInfo> infos;    // the patchInfo tile
    EncodedPatch encoded;                    // the patch writePatch is writing
    HeightUnits units;

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

    // Writes `payload` (possibly empty: an absent patch) as the pixel of patch (tx, ty).
    Status writePayload(int tx, int ty, std::span<const std::uint32_t> payload) {
        try {
            auto count = static_cast<unsigned int>(payload.size());
            // OpenEXR's slices are not const; writing only reads them.
            char* samples =
                reinterpret_cast<char*>(const_cast<std::uint32_t*>(payload.data()));
            patchesPart->setFrameBuffer(shard::payloadFrame(count, samples));
            patchesPart->writeTile(tx, ty);
        } catch (const std::exception& e) {
            return failFromException(e.what());
        }
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
            patchesPart.reset();
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

const std::filesystem::path& ShardWriter::path() const { return m_impl->file->path(); }
const ShardId& ShardWriter::shard() const { return m_impl->shard; }

Result<ShardWriter> ShardWriter::create(const std::filesystem::path& finalPath,
                                        const PyramidLayout& layout, const ShardId& shardId,
                                        bool withMask, const ShardWriterOptions& options) {
    TERRAIN_ASSERT(layout.contains(shardId), "shard outside the pyramid");
    if (options.compressionLevel < 0 || options.compressionLevel > shard::kMaxCompressionLevel)
        return Error{fmt::format("{}: compression level {}: must be from 0 (uncompressed) to {}",
                                 finalPath.string(), options.compressionLevel,
                                 shard::kMaxCompressionLevel)};

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
    impl->compressionLevel = options.compressionLevel;
    impl->cx = layout.shardCountX(shardId);
    impl->cy = layout.shardCountY(shardId);
    impl->tile = layout.tileSamples();
    impl->blocks = layout.blocksPerSide();
    impl->file.emplace(std::move(file).value());
    const auto patches = static_cast<std::size_t>(impl->cx) * static_cast<std::size_t>(impl->cy);
    impl->patchWritten.assign(patches, 0);
    impl->infos.assign(patches, shard::StoredInfo{});

    Result<std::unique_ptr<ExrFileStream>> stream =
        ExrFileStream::open(impl->file->temporaryPath(), finalPath.string());
    if (!stream) return stream.error();
    impl->stream = std::move(stream).value();
    try {
        const std::vector<Imf::Header> headers =
            shard::shardHeaders(layout, shardId, withMask, options.compressionLevel);
        impl->exr = std::make_unique<Imf::MultiPartOutputFile>(*impl->stream, headers.data(),
                                                               static_cast<int>(headers.size()));
        impl->patchesPart =
            std::make_unique<Imf::DeepTiledOutputPart>(*impl->exr, shard::kPatchesIndex);
        impl->infoPart = std::make_unique<Imf::TiledOutputPart>(*impl->exr, shard::kPatchInfoIndex);
    } catch (const std::exception& e) {
        return impl->failFromException(e.what()).error();
    }
    return ShardWriter(std::move(impl));
}

void encodePatch(const PatchRecord& record, std::span<const float> parentSamples,
                 const PyramidLayout& layout, bool withMask, const ShardWriterOptions& options,
                 EncodedPatch& out) {
    const int tile = layout.tileSamples();
    const auto tile2 = static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile);
    const auto blocks = static_cast<std::size_t>(layout.blocksPerSide());
    TERRAIN_ASSERT(record.heights.size() == tile2, "heights must hold tileSamples² values");
    TERRAIN_ASSERT(record.valid.size() == (withMask ? tile2 : 0),
                   "valid must hold tileSamples² values with a mask, none without");
    TERRAIN_ASSERT(record.blockErrors.size() == blocks * blocks,
                   "blockErrors must hold blocksPerSide² entries");
    TERRAIN_ASSERT(record.info.present, "only present patches are written");
    TERRAIN_ASSERT(parentSamples.empty() || record.id.level > 0, "the root has no parent");
    // Scratch of one patch, kept per thread so that encoding allocates nothing per patch.
    thread_local std::vector<BlockErrors> lambdas;        // rounded up to halves
    thread_local std::vector<std::uint16_t> halfLambdas;  // the same as HALF bits
    thread_local std::vector<std::uint32_t> codes;        // the height codes
    out.id = record.id;
    out.info = record.info;
    // The block errors as stored: rounded up to halves, and checksummed so.
    lambdas.resize(record.blockErrors.size());
    for (std::size_t b = 0; b < record.blockErrors.size(); ++b)
        for (std::size_t d = 0; d < kMaxSimplification; ++d)
            lambdas[b][d] = roundUpToHalf(record.blockErrors[b][d]);
    out.info.crc32 = patchChecksum(record.heights, record.valid, lambdas, out.info);
    codes.resize(tile2);
    const HeightEncoding encoding =
        encodeHeights(record.heights, tile, codes, options.units, parentSamples);
    out.heightDivisor = encoding.divisor;
    halfLambdas.clear();
    for (const BlockErrors& block : lambdas)
        for (const float lambda : block)
            halfLambdas.push_back(Imath::half(lambda).bits());  // exact: already a half
    shard::packPatchPayload(codes, encoding.prediction, record.valid, halfLambdas,
                            options.compressionLevel, out.payload);
}

Status ShardWriter::writePatch(const PatchRecord& record, std::span<const float> parentSamples) {
    Impl& w = *m_impl;
    if (w.failure) return *w.failure;
    ShardWriterOptions options;
    options.compressionLevel = w.compressionLevel;
    options.units = w.units;
    encodePatch(record, parentSamples, w.layout, w.withMask, options, w.encoded);
    return writeEncoded(w.encoded);
}

Status ShardWriter::writeEncoded(const EncodedPatch& patch) {
    Impl& w = *m_impl;
    if (w.failure) return *w.failure;
    TERRAIN_ASSERT(!w.finished, "ShardWriter::writeEncoded after finish()");
    const PyramidLayout& layout = w.layout;
    TERRAIN_ASSERT(layout.contains(patch.id) && layout.shardOf(patch.id) == w.shard,
                   "patch outside this shard");
    const auto tx = static_cast<int>(patch.id.x - layout.shardFirstX(w.shard));
    const auto ty = static_cast<int>(patch.id.y - layout.shardFirstY(w.shard));
    const std::size_t index = static_cast<std::size_t>(ty) * static_cast<std::size_t>(w.cx) +
                              static_cast<std::size_t>(tx);
    TERRAIN_ASSERT(w.patchWritten[index] == 0, "patch written twice");
    w.infos[index] = shard::toStored(patch.info, patch.heightDivisor);
    w.patchWritten[index] = 1;
    return w.writePayload(tx, ty, patch.payload);
}

Status ShardWriter::finish() {
    Impl& w = *m_impl;
    if (w.failure) return *w.failure;
    TERRAIN_ASSERT(!w.finished, "ShardWriter::finish() called twice");
    w.finished = true;
    // Every tile of a part must be written: an absent patch's payload has no samples.
    for (int ty = 0; ty < w.cy; ++ty)
        for (int tx = 0; tx < w.cx; ++tx)
            if (w.patchWritten[static_cast<std::size_t>(ty * w.cx + tx)] == 0)
                if (Status written = w.writePayload(tx, ty, {}); !written) return written;
    if (Status written = w.writeInfo(); !written) return written;
    if (Status closed = w.closeFile(); !closed) return closed;
    if (Status committed = w.file->commit(); !committed) return w.fail(committed.error().message);
    return {};
}

}  // namespace terrain::io
