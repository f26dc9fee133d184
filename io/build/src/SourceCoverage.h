// SourceCoverage: what a build says about how much of a source is data. A source without a
// valid sample would build a pyramid of nothing, silently: it is refused. One mostly of
// no-data builds, with a warning, since the filled samples are guesses from their
// neighbours and such a file is often the wrong band or the wrong no-data value.
#pragma once

#include "terrain/base/Result.h"

#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <string>

namespace terrain::io {

inline Status refuseEmptySource(const std::string& path, std::int64_t samples,
                                std::int64_t validSamples) {
    if (validSamples > 0) return {};
    return Error{fmt::format(
        "{}: no valid sample: all {} samples are no-data or NaN (a wrong band, or a wrong "
        "--nodata?)",
        path, samples)};
}

/// A warning when more than half of the samples are no-data; nullopt otherwise.
inline std::optional<std::string> mostlyNoDataWarning(const std::string& path, std::int64_t samples,
                                                      std::int64_t validSamples) {
    if (samples <= 0 || 2 * validSamples >= samples) return std::nullopt;
    return fmt::format(
        "{}: {:.1f} % of its {} samples are no-data; the pyramid fills them from their "
        "neighbours",
        path, 100.0 * static_cast<double>(samples - validSamples) / static_cast<double>(samples),
        samples);
}

}  // namespace terrain::io
