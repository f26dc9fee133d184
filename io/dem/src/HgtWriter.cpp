// The SRTM .hgt backend of writeHeightImage: a headerless square of big-endian int16 whole
// metres, north row first (what HgtDemReader reads). Heights are rounded to the nearest
// metre and clamped to ±32767, since −32768 is SRTM's void; a NaN is written as a void.
#include "HeightImageBackends.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

namespace terrain::io::detail {

Status writeHgt(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                std::int64_t width, std::int64_t height, const HeightRowSource& source,
                const HeightImageOptions& options, HeightImageSummary& summary) {
    std::FILE* out = std::fopen(file.c_str(), "wb");
    if (out == nullptr)
        return Error{
            fmt::format("{}: cannot write: {}", displayPath.string(), std::strerror(errno))};
    HeightStats stats;
    std::vector<float> band;
    std::vector<unsigned char> bytes;
    const std::int64_t bandRows = std::max<std::int64_t>(1, options.bandRows);
    bool ok = true;
    for (std::int64_t row = 0; row < height && ok; row += bandRows) {
        const std::int64_t rows = std::min(bandRows, height - row);
        band.resize(static_cast<std::size_t>(rows * width));
        source(row, rows, band);
        stats.add(band);
        bytes.resize(band.size() * 2);
        for (std::size_t i = 0; i < band.size(); ++i) {
            const float h = band[i];
            const auto v = static_cast<std::int16_t>(
                std::isnan(h) ? -32768 : std::clamp(std::lround(h), -32767L, 32767L));
            const auto u = static_cast<std::uint16_t>(v);
            bytes[2 * i] = static_cast<unsigned char>(u >> 8);
            bytes[2 * i + 1] = static_cast<unsigned char>(u & 0xFF);
        }
        ok = std::fwrite(bytes.data(), 1, bytes.size(), out) == bytes.size();
        if (options.progress) options.progress(double(row + rows) / double(height));
    }
    ok = std::fclose(out) == 0 && ok;
    if (!ok)
        return Error{
            fmt::format("{}: cannot write: {}", displayPath.string(), std::strerror(errno))};
    stats.storeIn(summary);
    return {};
}

}  // namespace terrain::io::detail
