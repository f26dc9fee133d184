// The per-format writers behind writeHeightImage (HeightImageWriter.cpp): each writes the
// finished file to `file` (an AtomicFile's temporary path), names `displayPath` in its
// errors, and fills in the summary's statistics.
#pragma once

#include "terrain/dem/HeightImageWriter.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::io::detail {

/// Running minimum / maximum of the finite samples, and a count of the others.
struct HeightStats {
    float min = std::numeric_limits<float>::infinity();
    float max = -std::numeric_limits<float>::infinity();
    std::uint64_t nonFinite = 0;

    void add(std::span<const float> heights) {
        for (const float h : heights) {
            if (!std::isfinite(h)) {
                ++nonFinite;
                continue;
            }
            min = std::min(min, h);
            max = std::max(max, h);
        }
    }
    void storeIn(HeightImageSummary& summary) const {
        const bool any = min <= max;
        summary.minHeightM = any ? min : 0.0F;
        summary.maxHeightM = any ? max : 0.0F;
        summary.nonFiniteSamples = nonFinite;
    }
};

Status writeGeoTiff(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                    std::int64_t width, std::int64_t height, const HeightRowSource& source,
                    const HeightImageOptions& options, HeightImageSummary& summary);

Status writePng16(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                  std::int64_t width, std::int64_t height, const HeightRowSource& source,
                  const HeightImageOptions& options, HeightImageSummary& summary);

Status writeExr(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                std::int64_t width, std::int64_t height, const HeightRowSource& source,
                const HeightImageOptions& options, HeightImageSummary& summary);

Status writeHgt(const std::filesystem::path& file, const std::filesystem::path& displayPath,
                std::int64_t width, std::int64_t height, const HeightRowSource& source,
                const HeightImageOptions& options, HeightImageSummary& summary);

}  // namespace terrain::io::detail
