// Cheap structural checks that a PNG or JPEG file is whole, run before OpenImageIO
// decodes it. Their decoders handle a cut file badly: libjpeg returns grey rows with only
// a warning, and OpenImageIO 2.4's PNG reader leaks its message when libpng hits the
// end of the file. Both checks read a few bytes per chunk, never the pixel data.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace terrain::io::detail {

/// "truncated: …" when a PNG chunk runs past the end of the file or IEND is missing.
/// nullopt for a whole file, or for one that is not a PNG (the decoder then says so).
std::optional<std::string> findPngTruncation(const std::string& path, std::uint64_t fileBytes);

/// "truncated: …" when a JPEG lacks its end-of-image marker (FF D9) in its last KiB.
std::optional<std::string> findJpegTruncation(const std::string& path, std::uint64_t fileBytes);

}  // namespace terrain::io::detail
