// CRC-32 of a patch's stored samples (see PatchChecksum.h), with zlib's crc32, fed in
// chunks so nothing is allocated per patch.
#include "PatchChecksum.h"

#include "ShardFormat.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <type_traits>

namespace terrain::io {
namespace {

constexpr std::size_t kChunk = 1024;  // values converted per crc32 call

std::uint16_t halfBits(std::uint8_t valid) { return valid != 0 ? 0x3C00U : 0x0000U; }

// Little-endian bytes of the values, whatever the host's byte order.
template <typename T>
void storeLittleEndian(T value, unsigned char* out) {
    using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint16_t>;
    static_assert(sizeof(T) == sizeof(Bits));
    const auto bits = std::bit_cast<Bits>(value);
    for (std::size_t b = 0; b < sizeof(T); ++b)
        out[b] = static_cast<unsigned char>((bits >> (8U * b)) & 0xFFU);
}

uLong addBytes(uLong crc, const void* data, std::size_t size) {
    return crc32_z(crc, static_cast<const Bytef*>(data), size);
}

uLong addFloats(uLong crc, std::span<const float> values) {
    if constexpr (std::endian::native == std::endian::little) {
        return addBytes(crc, values.data(), values.size_bytes());
    } else {
        std::array<unsigned char, kChunk * 4> bytes;
        for (std::size_t i = 0; i < values.size(); i += kChunk) {
            const std::size_t n = std::min(kChunk, values.size() - i);
            for (std::size_t k = 0; k < n; ++k) storeLittleEndian(values[i + k], &bytes[4 * k]);
            crc = addBytes(crc, bytes.data(), 4 * n);
        }
        return crc;
    }
}

}  // namespace

std::uint32_t patchChecksum(std::span<const float> heights, std::span<const std::uint8_t> valid,
                            std::span<const BlockErrors> blockErrors, const PatchInfo& info) {
    uLong crc = crc32_z(0L, Z_NULL, 0);
    crc = addFloats(crc, heights);
    std::array<unsigned char, kChunk * 4> bytes;
    for (std::size_t i = 0; i < valid.size(); i += kChunk) {
        const std::size_t n = std::min(kChunk, valid.size() - i);
        for (std::size_t k = 0; k < n; ++k)
            storeLittleEndian(halfBits(valid[i + k]), &bytes[2 * k]);
        crc = addBytes(crc, bytes.data(), 2 * n);
    }
    for (std::size_t d = 0; d < kMaxSimplification; ++d) {
        for (std::size_t i = 0; i < blockErrors.size(); i += kChunk) {
            const std::size_t n = std::min(kChunk, blockErrors.size() - i);
            for (std::size_t k = 0; k < n; ++k)
                storeLittleEndian(blockErrors[i + k][d], &bytes[4 * k]);
            crc = addBytes(crc, bytes.data(), 4 * n);
        }
    }
    unsigned char* out = bytes.data();
    storeLittleEndian(shard::storedPresent(info), out);
    storeLittleEndian(info.minHeight, out + 4);
    storeLittleEndian(info.maxHeight, out + 8);
    storeLittleEndian(info.error, out + 12);
    storeLittleEndian(info.approxError, out + 16);
    storeLittleEndian(info.quantError, out + 20);
    storeLittleEndian(info.noDataSamples, out + 24);
    crc = addBytes(crc, out, 28);
    return static_cast<std::uint32_t>(crc);
}

}  // namespace terrain::io
