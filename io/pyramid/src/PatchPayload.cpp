// Packing and unpacking one patch's payload (see PatchPayload.h).
#include "PatchPayload.h"

#include "terrain/base/Assert.h"

#include <fmt/format.h>
#include <half.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>

namespace terrain::io::shard {
namespace {

static_assert(std::endian::native == std::endian::little,
              "a payload's bytes are those of the little-endian words OpenEXR stores");

// The first word of a payload: byte 0 the codec, byte 1 the bytes per height code (1 … 4),
// byte 2 the height prediction, byte 3 zero. The second: the length in bytes of the data that
// follows.
constexpr std::uint8_t kStored = 0;
constexpr std::uint8_t kZstd = 1;
constexpr std::size_t kHeaderWords = 2;
// zstd's shortest match searched for (ZSTD_c_minMatch; its largest is 7).
constexpr int kMinMatch = 7;

struct CompressContextDeleter {
    void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
struct DecompressContextDeleter {
    void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

// One context and one scratch buffer per thread, reused for every patch it packs or unpacks.
ZSTD_CCtx& compressContext() {
    thread_local std::unique_ptr<ZSTD_CCtx, CompressContextDeleter> context(ZSTD_createCCtx());
    TERRAIN_ASSERT(context != nullptr, "ZSTD_createCCtx failed");
    return *context;
}

ZSTD_DCtx& decompressContext() {
    thread_local std::unique_ptr<ZSTD_DCtx, DecompressContextDeleter> context(ZSTD_createDCtx());
    TERRAIN_ASSERT(context != nullptr, "ZSTD_createDCtx failed");
    return *context;
}

std::vector<std::uint8_t>& planesScratch() {
    thread_local std::vector<std::uint8_t> bytes;
    return bytes;
}

int codeBytes(std::span<const std::uint32_t> codes) {
    const std::uint32_t largest = codes.empty() ? 0 : *std::max_element(codes.begin(), codes.end());
    return largest < (1U << 8) ? 1 : largest < (1U << 16) ? 2 : largest < (1U << 24) ? 3 : 4;
}

std::vector<std::size_t>& sectionsScratch() {
    thread_local std::vector<std::size_t> offsets;
    return offsets;
}

// What compressSections may write at most: zstd's bound for the whole, plus a block header
// (3 bytes) for each section that may end a block early.
std::size_t sectionsBound(std::size_t bytes, std::size_t sections) {
    return ZSTD_compressBound(bytes) + 3 * sections;
}

// One zstd frame (RFC 8878) of `bytes`, with a block ending at each offset in `sections`
// (ZSTD_e_flush): each block carries its own entropy tables, so the busy low byte plane of
// the codes, their nearly empty high planes, the mask and λ's low and high bytes are each
// coded with statistics of their own instead of one table for all (issue 52: 5 % of an 8-bit
// DEM's pyramid). Matches still reach back across blocks, and any zstd decoder reads the
// frame as before. Matches shorter than 7 bytes are not looked for: in runs of small codes
// they cost more than the literals they replace (2 % more on the same DEM).
std::size_t compressSections(std::span<const std::uint8_t> bytes,
                             std::span<const std::size_t> sections, int level, std::uint8_t* out,
                             std::size_t capacity) {
    ZSTD_CCtx& context = compressContext();
    ZSTD_CCtx_reset(&context, ZSTD_reset_session_and_parameters);
    ZSTD_CCtx_setParameter(&context, ZSTD_c_compressionLevel, level);
    ZSTD_CCtx_setParameter(&context, ZSTD_c_minMatch, kMinMatch);
    ZSTD_CCtx_setPledgedSrcSize(&context, bytes.size());
    ZSTD_outBuffer output{out, capacity, 0};
    for (std::size_t k = 0; k < sections.size(); ++k) {
        const bool last = k + 1 == sections.size();
        const std::size_t end = last ? bytes.size() : sections[k + 1];
        TERRAIN_ASSERT(sections[k] <= end && end <= bytes.size(), "compressSections: offsets");
        if (end == sections[k] && !last) continue;
        ZSTD_inBuffer input{bytes.data() + sections[k], end - sections[k], 0};
        std::size_t pending = 0;
        do {
            const std::size_t before = output.pos + input.pos;
            pending =
                ZSTD_compressStream2(&context, &output, &input, last ? ZSTD_e_end : ZSTD_e_flush);
            TERRAIN_ASSERT(!ZSTD_isError(pending), "ZSTD_compressStream2 failed");
            TERRAIN_ASSERT(pending == 0 || output.pos + input.pos > before,
                           "compressSections: output buffer too small");
        } while (pending != 0);
    }
    return output.pos;
}

std::size_t unpackedBytes(const PayloadShape& shape, int bytesPerCode) {
    const auto samples =
        static_cast<std::size_t>(shape.tileSamples) * static_cast<std::size_t>(shape.tileSamples);
    const auto blocks = static_cast<std::size_t>(shape.blocksPerSide) *
                        static_cast<std::size_t>(shape.blocksPerSide);
    return samples * static_cast<std::size_t>(bytesPerCode) + (shape.withMask ? samples : 0) +
           blocks * kMaxSimplification * 2;
}

std::size_t wordsFor(std::size_t bytes) { return kHeaderWords + (bytes + 3) / 4; }

}  // namespace

void packPatchPayload(std::span<const std::uint32_t> codes, HeightPrediction prediction,
                      std::span<const std::uint8_t> valid,
                      std::span<const std::uint16_t> halfLambdas, int level,
                      std::vector<std::uint32_t>& words) {
    TERRAIN_ASSERT(level >= 0 && level <= kMaxCompressionLevel, "packPatchPayload: level");
    const int bytesPerCode = codeBytes(codes);
    std::vector<std::uint8_t>& planes = planesScratch();
    planes.resize(codes.size() * static_cast<std::size_t>(bytesPerCode) + valid.size() +
                  halfLambdas.size() * 2);
    std::uint8_t* out = planes.data();
    for (int plane = 0; plane < bytesPerCode; ++plane) {
        const int shift = 8 * plane;
        for (const std::uint32_t code : codes) *out++ = static_cast<std::uint8_t>(code >> shift);
    }
    // Where each part of the data starts: the codes' byte planes, the mask, λ's low and
    // high bytes.
    std::vector<std::size_t>& sections = sectionsScratch();
    sections.clear();
    for (int plane = 0; plane <= bytesPerCode; ++plane)
        sections.push_back(codes.size() * static_cast<std::size_t>(plane));
    sections.push_back(sections.back() + valid.size());
    sections.push_back(sections.back() + halfLambdas.size());
    out = std::copy(valid.begin(), valid.end(), out);
    // λ(1) of every block, then λ(2) …: neighbouring blocks' bounds are alike, one block's
    // four are not.
    for (int shift = 0; shift <= 8; shift += 8)
        for (std::size_t d = 0; d < kMaxSimplification; ++d)
            for (std::size_t k = d; k < halfLambdas.size(); k += kMaxSimplification)
                *out++ = static_cast<std::uint8_t>(halfLambdas[k] >> shift);

    std::uint8_t codec = kStored;
    std::size_t length = planes.size();
    words.assign(
        wordsFor(level > 0 ? sectionsBound(planes.size(), sections.size()) : planes.size()), 0U);
    auto* data = reinterpret_cast<std::uint8_t*>(words.data() + kHeaderWords);
    if (level > 0) {
        const std::size_t packed =
            compressSections(planes, sections, level, data, (words.size() - kHeaderWords) * 4);
        if (packed < planes.size()) {
            codec = kZstd;
            length = packed;
        }
    }
    if (codec == kStored) std::memcpy(data, planes.data(), planes.size());
    words.resize(wordsFor(length));
    // Zero padding after the data, so equal patches give equal files.
    std::memset(data + length, 0, (words.size() - kHeaderWords) * 4 - length);
    words[0] = std::uint32_t{codec} | (static_cast<std::uint32_t>(bytesPerCode) << 8) |
               (static_cast<std::uint32_t>(prediction) << 16);
    words[1] = static_cast<std::uint32_t>(length);
}

Status unpackPatchPayload(std::span<const std::uint32_t> words, const PayloadShape& shape,
                          std::vector<std::uint32_t>& codes, HeightPrediction& prediction,
                          std::vector<std::uint8_t>& valid, std::vector<BlockErrors>& blockErrors) {
    if (words.size() < kHeaderWords)
        return Error{fmt::format("payload of {} samples, shorter than its header", words.size())};
    const std::uint32_t codec = words[0] & 0xFFU;
    const std::uint32_t bytesPerCode = (words[0] >> 8) & 0xFFU;
    const std::uint32_t predictionByte = (words[0] >> 16) & 0xFFU;
    if (codec > kZstd || bytesPerCode < 1 || bytesPerCode > 4 ||
        predictionByte >= kHeightPredictions || (words[0] >> 24) != 0)
        return Error{fmt::format("payload header 0x{:08x} is not one a writer makes", words[0])};
    prediction = static_cast<HeightPrediction>(predictionByte);
    const std::size_t length = words[1];
    if (wordsFor(length) != words.size())
        return Error{
            fmt::format("payload says {} bytes of data but has {} samples", length, words.size())};
    const std::size_t expected = unpackedBytes(shape, static_cast<int>(bytesPerCode));
    const auto* data = reinterpret_cast<const std::uint8_t*>(words.data() + kHeaderWords);
    const std::uint8_t* planes = data;
    if (codec == kZstd) {
        std::vector<std::uint8_t>& scratch = planesScratch();
        scratch.resize(expected);
        const std::size_t unpacked =
            ZSTD_decompressDCtx(&decompressContext(), scratch.data(), expected, data, length);
        if (ZSTD_isError(unpacked))
            return Error{
                fmt::format("payload does not decompress: {}", ZSTD_getErrorName(unpacked))};
        if (unpacked != expected)
            return Error{
                fmt::format("payload decompresses to {} bytes, expected {}", unpacked, expected)};
        planes = scratch.data();
    } else if (length != expected) {
        return Error{fmt::format("stored payload of {} bytes, expected {}", length, expected)};
    }

    const auto samples =
        static_cast<std::size_t>(shape.tileSamples) * static_cast<std::size_t>(shape.tileSamples);
    codes.assign(samples, 0U);
    for (std::uint32_t plane = 0; plane < bytesPerCode; ++plane) {
        const std::uint32_t shift = 8 * plane;
        const std::uint8_t* in = planes + plane * samples;
        for (std::size_t i = 0; i < samples; ++i) codes[i] |= std::uint32_t{in[i]} << shift;
    }
    const std::uint8_t* mask = planes + bytesPerCode * samples;
    valid.assign(mask, mask + (shape.withMask ? samples : 0));
    for (std::size_t i = 0; i < valid.size(); ++i)
        if (valid[i] > 1)
            return Error{fmt::format("mask sample ({}, {}) is {}, neither 0 nor 1",
                                     i % static_cast<std::size_t>(shape.tileSamples),
                                     i / static_cast<std::size_t>(shape.tileSamples), valid[i])};
    const std::uint8_t* lambdas = mask + valid.size();
    const auto blocks = static_cast<std::size_t>(shape.blocksPerSide) *
                        static_cast<std::size_t>(shape.blocksPerSide);
    const std::size_t halves = blocks * kMaxSimplification;
    blockErrors.resize(blocks);
    for (std::size_t d = 0; d < kMaxSimplification; ++d)
        for (std::size_t b = 0; b < blocks; ++b) {
            const std::size_t k = d * blocks + b;
            Imath::half value;
            value.setBits(static_cast<std::uint16_t>(lambdas[k] | (lambdas[halves + k] << 8)));
            blockErrors[b][d] = value;
        }
    return {};
}

std::size_t maxPayloadWords(const PayloadShape& shape) {
    return wordsFor(std::max(ZSTD_compressBound(unpackedBytes(shape, 4)), unpackedBytes(shape, 4)));
}

}  // namespace terrain::io::shard
