// OpenEXR file layout ("OpenEXR File Layout", openexr.com): magic 20000630 (76 2f 31 01),
// a 4-byte version field (version 2 in the low byte; flags: 0x200 single-part tiled,
// 0x400 long names, 0x800 deep data, 0x1000 multi-part), then the header(s).
#include "terrain/io/ExrHeaderCheck.h"

#include <fmt/format.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <system_error>

namespace terrain::io {

namespace {

constexpr std::uint32_t kMagic = 20000630;
constexpr std::uint32_t kMultiPartFlag = 0x1000;
constexpr std::uint32_t kLongNamesFlag = 0x400;

std::uint32_t littleEndian32(const unsigned char* b) {
    return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8U | std::uint32_t{b[2]} << 16U |
           std::uint32_t{b[3]} << 24U;
}

// A null-terminated name of at most maxLength characters; false when the file ends first
// or the name is longer.
bool readName(std::ifstream& in, std::size_t maxLength, std::string& name) {
    name.clear();
    for (char c = 0; in.get(c);) {
        if (c == '\0') return true;
        if (name.size() == maxLength) return false;
        name.push_back(c);
    }
    return false;
}

}  // namespace

Status checkExrHeaderSizes(const std::filesystem::path& path) {
    std::error_code ec;
    const std::uintmax_t fileSize = std::filesystem::file_size(path, ec);
    if (ec) return Error{"cannot read its size: " + ec.message()};
    std::ifstream in(path, std::ios::binary);
    unsigned char start[8] = {};
    if (!in.read(reinterpret_cast<char*>(start), sizeof start))
        return Error{"not an OpenEXR file: shorter than its 8-byte start"};
    if (littleEndian32(start) != kMagic) return Error{"not an OpenEXR file: no magic number"};
    const std::uint32_t version = littleEndian32(start + 4);
    const bool multiPart = (version & kMultiPartFlag) != 0;
    const std::size_t maxName = (version & kLongNamesFlag) != 0 ? 255 : 31;

    std::string name, type;
    for (int part = 0;; ++part) {
        if (multiPart && in.peek() == 0) break;  // the empty header after the last one
        // One header: attributes until an empty name.
        while (true) {
            if (!readName(in, maxName, name))
                return Error{
                    fmt::format("corrupt OpenEXR header {}: an attribute name runs "
                                "past the end of the file or its length limit",
                                part)};
            if (name.empty()) break;
            if (!readName(in, maxName, type))
                return Error{fmt::format("corrupt OpenEXR header {}: attribute '{}' has no type",
                                         part, name)};
            unsigned char sizeBytes[4] = {};
            if (!in.read(reinterpret_cast<char*>(sizeBytes), sizeof sizeBytes))
                return Error{fmt::format("corrupt OpenEXR header {}: attribute '{}' has no size",
                                         part, name)};
            const auto size = static_cast<std::int32_t>(littleEndian32(sizeBytes));
            const auto at = static_cast<std::uintmax_t>(in.tellg());
            if (size < 0 || static_cast<std::uintmax_t>(size) > fileSize - at)
                return Error{
                    fmt::format("corrupt OpenEXR header {}: attribute '{}' ({}) says "
                                "it has {} bytes, the file has {} left",
                                part, name, type, size, fileSize - at)};
            in.seekg(size, std::ios::cur);
        }
        if (!multiPart) break;
    }
    return {};
}

}  // namespace terrain::io
