// PNG chunk walk (PNG spec, ISO/IEC 15948 §5.3: length, type, data, CRC) and the JPEG
// end-of-image marker check (ITU T.81 §B.2.1).
#include "ImageFileTruncation.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <vector>

namespace terrain::io::detail {

namespace {

constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P',  'N',  'G',
                                                        '\r', '\n', 0x1A, '\n'};
constexpr std::uint64_t kPngChunkOverhead = 12;  // length, type, CRC
constexpr std::uint64_t kJpegTailBytes = 1024;   // room for trailing padding

}  // namespace

std::optional<std::string> findPngTruncation(const std::string& path, std::uint64_t fileBytes) {
    std::ifstream in(path, std::ios::binary);
    std::array<unsigned char, 8> signature{};
    in.read(reinterpret_cast<char*>(signature.data()), signature.size());
    if (in.gcount() != 8 || signature != kPngSignature) return std::nullopt;
    std::uint64_t at = signature.size();
    while (true) {
        if (at + kPngChunkOverhead > fileBytes)
            return fmt::format("truncated: the PNG file ends at byte {} without its IEND chunk",
                               fileBytes);
        std::array<unsigned char, 8> header{};
        in.seekg(static_cast<std::streamoff>(at));
        in.read(reinterpret_cast<char*>(header.data()), header.size());
        if (in.gcount() != 8) return "truncated: cannot read a PNG chunk header";
        const std::uint64_t length = (std::uint64_t{header[0]} << 24U) |
                                     (std::uint64_t{header[1]} << 16U) |
                                     (std::uint64_t{header[2]} << 8U) | header[3];
        const std::string type(reinterpret_cast<const char*>(header.data() + 4), 4);
        if (at + kPngChunkOverhead + length > fileBytes)
            return fmt::format(
                "truncated: PNG chunk {} at byte {} ends past the end of the file "
                "(byte {} of {})",
                type, at, at + kPngChunkOverhead + length, fileBytes);
        if (type == "IEND") return std::nullopt;
        at += kPngChunkOverhead + length;
    }
}

std::optional<std::string> findJpegTruncation(const std::string& path, std::uint64_t fileBytes) {
    const std::uint64_t tail = std::min(kJpegTailBytes, fileBytes);
    std::ifstream in(path, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(fileBytes - tail));
    std::vector<unsigned char> bytes(static_cast<std::size_t>(tail));
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    for (std::size_t i = 0; i + 1 < bytes.size(); ++i)
        if (bytes[i] == 0xFF && bytes[i + 1] == 0xD9) return std::nullopt;
    return std::string("truncated: no JPEG end-of-image marker (FF D9) at the end of the file");
}

}  // namespace terrain::io::detail
