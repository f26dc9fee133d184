// 8-bit RGBA PNG frames through OpenImageIO and an AtomicFile.
#include "terrain/dem/RgbaImageWriter.h"

#include "terrain/base/AtomicFile.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include <limits>
#include <string>

namespace terrain::io {

Status writeRgba8Png(const std::filesystem::path& path, std::int64_t width, std::int64_t height,
                     std::span<const std::uint8_t> pixels) {
    TERRAIN_ASSERT(
        width >= 0 && height >= 0 &&
            pixels.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4,
        "pixels do not match width × height × 4");
    if (width < 1 || height < 1 || width > std::numeric_limits<int>::max() ||
        height > std::numeric_limits<int>::max())
        return Error{fmt::format("{}: cannot write a {} × {} PNG", path.string(), width, height)};
    return writeAtomically(path, [&](const std::filesystem::path& file) -> Status {
        const auto fail = [&](const std::string& what) {
            return Error{fmt::format("{}: cannot write PNG: {}", path.string(), what)};
        };
        std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file.string());
        if (!out) return fail(OIIO::geterror());
        OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 4,
                             OIIO::TypeDesc::UINT8);
        // The pixels are straight (unassociated) RGBA like PNG itself: no conversion.
        spec.attribute("oiio:UnassociatedAlpha", 1);
        if (!out->open(file.string(), spec)) return fail(out->geterror());
        if (!out->write_image(OIIO::TypeDesc::UINT8, pixels.data())) {
            std::string message = out->geterror();
            out->close();
            return fail(message);
        }
        if (!out->close()) return fail(out->geterror());
        return {};
    });
}

}  // namespace terrain::io
