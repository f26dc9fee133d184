// The 16-bit PNG and OpenEXR height writers, through OpenImageIO's scanline interface, a
// band of rows at a time.
#include "HeightImageBackends.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace terrain::io::detail {

namespace {

std::int64_t bandRowsOf(const HeightImageOptions& options) {
    return std::max<std::int64_t>(1, options.bandRows);
}

// Opens `file` for writing with `spec`, hands each band of rows to `convertAndWrite`,
// closes. Errors carry OpenImageIO's message.
template <typename WriteBand>
Status writeScanlines(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                      const char* formatLabel, const OIIO::ImageSpec& spec, std::int64_t height,
                      std::int64_t bandRows, WriteBand&& writeBand) {
    const auto fail = [&](const std::string& what) {
        return Error{
            fmt::format("{}: cannot write {}: {}", displayPath.string(), formatLabel, what)};
    };
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file.string());
    if (!out) return fail(OIIO::geterror());
    if (!out->open(file.string(), spec)) return fail(out->geterror());
    for (std::int64_t row0 = 0; row0 < height; row0 += bandRows) {
        const std::int64_t rows = std::min(bandRows, height - row0);
        if (!writeBand(*out, row0, rows)) {
            std::string message = out->geterror();
            out->close();
            return fail(message.empty() ? std::string("writing scanlines failed") : message);
        }
    }
    if (!out->close()) return fail(out->geterror());
    return {};
}

}  // namespace

Status writePng16(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                  std::int64_t width, std::int64_t height, const HeightRowSource& source,
                  const HeightImageOptions& options, HeightImageSummary& summary) {
    const std::int64_t bandRows = bandRowsOf(options);
    std::vector<float> band(static_cast<std::size_t>(width * std::min(bandRows, height)));
    const double passes = options.pngOffsetM ? 1.0 : 2.0;
    const auto report = [&](double pass, std::int64_t rowsDone) {
        if (options.progress)
            options.progress((pass + static_cast<double>(rowsDone) / static_cast<double>(height)) /
                             passes);
    };

    PngQuantisation q;
    q.scaleM = options.pngScaleM;
    if (options.pngOffsetM) {
        q.offsetM = *options.pngOffsetM;
    } else {
        // Grey 0 = the floor of the lowest height: a pass over the source to find it.
        HeightStats scan;
        for (std::int64_t row0 = 0; row0 < height; row0 += bandRows) {
            const std::int64_t rows = std::min(bandRows, height - row0);
            const std::span<float> part(band.data(), static_cast<std::size_t>(width * rows));
            source(row0, rows, part);
            scan.add(part);
            report(0.0, row0 + rows);
        }
        q.offsetM = scan.min <= scan.max ? std::floor(static_cast<double>(scan.min)) : 0.0;
    }

    OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 1,
                         OIIO::TypeDesc::UINT16);
    spec.channelnames = {"Y"};
    // How to get metres back, for whoever opens the file (a PNG "Description" text).
    spec.attribute("ImageDescription",
                   fmt::format("terrain heights: metres = {} + grey * {}", q.offsetM, q.scaleM));

    HeightStats stats;
    std::vector<std::uint16_t> grey(band.size());
    const double inverseScale = 1.0 / q.scaleM;
    const Status written = writeScanlines(
        file, displayPath, "PNG", spec, height, bandRows,
        [&](OIIO::ImageOutput& out, std::int64_t row0, std::int64_t rows) {
            const std::size_t n = static_cast<std::size_t>(width * rows);
            const std::span<float> part(band.data(), n);
            source(row0, rows, part);
            stats.add(part);
            for (std::size_t i = 0; i < n; ++i) {
                const double level =
                    std::nearbyint((static_cast<double>(part[i]) - q.offsetM) * inverseScale);
                if (!(level >= 0.0 && level <= 65535.0)) ++q.clampedSamples;  // NaN counts too
                grey[i] = static_cast<std::uint16_t>(
                    std::isnan(level) ? 0.0 : std::clamp(level, 0.0, 65535.0));
            }
            const bool ok =
                out.write_scanlines(static_cast<int>(row0), static_cast<int>(row0 + rows), 0,
                                    OIIO::TypeDesc::UINT16, grey.data());
            report(passes - 1.0, row0 + rows);
            return ok;
        });
    if (!written) return written;
    stats.storeIn(summary);
    summary.png = q;
    return {};
}

Status writeExr(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                std::int64_t width, std::int64_t height, const HeightRowSource& source,
                const HeightImageOptions& options, HeightImageSummary& summary) {
    const std::int64_t bandRows = bandRowsOf(options);
    std::vector<float> band(static_cast<std::size_t>(width * std::min(bandRows, height)));
    OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 1,
                         OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"Y"};
    spec.attribute("compression", "zip");  // lossless
    spec.attribute("ImageDescription", "terrain heights in metres");
    HeightStats stats;
    const Status written = writeScanlines(
        file, displayPath, "OpenEXR", spec, height, bandRows,
        [&](OIIO::ImageOutput& out, std::int64_t row0, std::int64_t rows) {
            const std::span<float> part(band.data(), static_cast<std::size_t>(width * rows));
            source(row0, rows, part);
            stats.add(part);
            const bool ok =
                out.write_scanlines(static_cast<int>(row0), static_cast<int>(row0 + rows), 0,
                                    OIIO::TypeDesc::FLOAT, part.data());
            if (options.progress)
                options.progress(static_cast<double>(row0 + rows) / static_cast<double>(height));
            return ok;
        });
    if (!written) return written;
    stats.storeIn(summary);
    return {};
}

}  // namespace terrain::io::detail
