// libtiff checks of a TIFF DEM before decoding (see TiffDemInspection.h).
#include "TiffDemInspection.h"

#include "DemReaderFactories.h"
#include "GeoTiffGeoreferenceTags.h"
#include "TiffFile.h"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cstring>
#include <fstream>
#include <string_view>

namespace terrain::io::detail {

namespace {

std::string sampleFormatName(std::uint16_t format) {
    switch (format) {
        case SAMPLEFORMAT_UINT:
            return "unsigned integer";
        case SAMPLEFORMAT_INT:
            return "signed integer";
        case SAMPLEFORMAT_IEEEFP:
            return "floating point";
        case SAMPLEFORMAT_VOID:
            return "untyped";
        case SAMPLEFORMAT_COMPLEXINT:
            return "complex integer";
        case SAMPLEFORMAT_COMPLEXIEEEFP:
            return "complex floating point";
        default:
            return fmt::format("SampleFormat {}", format);
    }
}

bool supportedSample(std::uint16_t format, std::uint16_t bits) {
    switch (format) {
        case SAMPLEFORMAT_UINT:
        case SAMPLEFORMAT_INT:
            return bits == 8 || bits == 16 || bits == 32;
        case SAMPLEFORMAT_IEEEFP:
            return bits == 16 || bits == 32 || bits == 64;
        default:
            return false;
    }
}

// GDAL keeps a band's scale and offset in its GDAL_METADATA XML as
// <Item name="SCALE" sample="0" role="scale">0.1</Item>; the first band's is the DEM's.
std::optional<double> gdalMetadataItem(const std::string& xml, std::string_view role) {
    const std::string roleAttribute = fmt::format("role=\"{}\"", role);
    for (std::size_t at = xml.find(roleAttribute); at != std::string::npos;
         at = xml.find(roleAttribute, at + 1)) {
        const std::size_t open = xml.rfind("<Item", at);
        const std::size_t close = xml.find('>', at);
        const std::size_t end = xml.find('<', close);
        if (open == std::string::npos || close == std::string::npos || end == std::string::npos)
            return std::nullopt;
        const std::string_view tag(xml.data() + open, close - open);
        if (tag.find("sample=") != std::string_view::npos &&
            tag.find("sample=\"0\"") == std::string_view::npos)
            continue;  // another band's
        const std::string text = xml.substr(close + 1, end - close - 1);
        double value = 0.0;
        const auto [last, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || last != text.data() + text.size()) return std::nullopt;
        return value;
    }
    return std::nullopt;
}

// When libtiff cannot open a file: a header whose first directory lies past the end of
// the file means a truncated download (libtiff writes the directory last), which says
// more than libtiff's "Can not read TIFF directory count".
std::optional<std::string> diagnoseTruncatedHeader(const std::string& path,
                                                   std::uint64_t fileBytes) {
    std::array<unsigned char, 16> header{};
    std::ifstream in(path, std::ios::binary);
    in.read(reinterpret_cast<char*>(header.data()), header.size());
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got < 8) return std::nullopt;
    const bool little = header[0] == 'I' && header[1] == 'I';
    const bool big = header[0] == 'M' && header[1] == 'M';
    if (!little && !big) return std::nullopt;
    const auto read = [&](std::size_t at, std::size_t bytes) {
        std::uint64_t value = 0;
        for (std::size_t i = 0; i < bytes; ++i) {
            const std::uint64_t byte = header[at + (little ? i : bytes - 1 - i)];
            value |= byte << (8U * i);
        }
        return value;
    };
    const std::uint64_t version = read(2, 2);
    std::uint64_t offset = 0;
    if (version == 42) {
        offset = read(4, 4);
    } else if (version == 43 && got >= 16) {
        offset = read(8, 8);
    } else {
        return std::nullopt;
    }
    if (offset < fileBytes) return std::nullopt;
    return fmt::format(
        "truncated: the TIFF directory at byte {} lies past the end of the file "
        "({} bytes)",
        offset, fileBytes);
}

}  // namespace

Result<TiffDemFacts> inspectTiffDem(const std::string& path, std::uint64_t fileBytes) {
    const auto fail = [&](const std::string& what) {
        return Error{fmt::format("{}: {}", path, what)};
    };
    TiffFile tiff(path, "r");
    if (!tiff) {
        if (const std::optional<std::string> truncated = diagnoseTruncatedHeader(path, fileBytes))
            return fail(*truncated);
        return fail(libraryMessage(tiff.error("cannot open as a TIFF file"), path));
    }
    TIFF* t = tiff.get();

    std::uint16_t bits = 1;
    std::uint16_t format = SAMPLEFORMAT_UINT;
    TIFFGetFieldDefaulted(t, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLEFORMAT, &format);
    if (!supportedSample(format, bits))
        return fail(fmt::format(
            "unsupported sample type: {}-bit {} (heights must be 8/16/32-bit integers or "
            "16/32/64-bit floats)",
            bits, sampleFormatName(format)));

    // Every strip or tile must lie inside the file: a truncated download otherwise decodes
    // as zeros or fails deep inside a later read.
    const bool tiled = TIFFIsTiled(t) != 0;
    const std::uint32_t count = tiled ? TIFFNumberOfTiles(t) : TIFFNumberOfStrips(t);
    for (std::uint32_t i = 0; i < count; ++i) {
        int error = 0;
        const std::uint64_t offset = TIFFGetStrileOffsetWithErr(t, i, &error);
        const std::uint64_t bytes = error == 0 ? TIFFGetStrileByteCountWithErr(t, i, &error) : 0;
        if (error != 0)
            return fail(tiff.error(
                fmt::format("cannot read the location of TIFF {} {}", tiled ? "tile" : "strip", i)
                    .c_str()));
        if (offset > fileBytes || bytes > fileBytes - offset)
            return fail(
                fmt::format("truncated: TIFF {} {} ends past the end of the file (byte {} of {})",
                            tiled ? "tile" : "strip", i, offset + bytes, fileBytes));
    }

    TiffDemFacts facts;
    std::uint16_t samplesPerPixel = 1;
    if (TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLESPERPIXEL, &samplesPerPixel) == 1)
        facts.samplesPerPixel = samplesPerPixel;
    if (hasFlippedOrRotatedPlacement(t)) {
        facts.flippedOrRotated = true;
        return facts;
    }
    Result<std::optional<Georeference>> geo = readGeoreferenceTags(t);
    if (!geo) return fail(geo.error().message);
    facts.georeference = geo.value();
    facts.noDataValue = readGdalNoDataTag(t);
    if (const std::optional<std::string> xml = readAsciiTag(t, kGdalMetadataTag)) {
        facts.scale = gdalMetadataItem(*xml, "scale");
        facts.offset = gdalMetadataItem(*xml, "offset");
    }
    return facts;
}

}  // namespace terrain::io::detail
