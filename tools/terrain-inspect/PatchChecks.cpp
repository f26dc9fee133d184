// Per-patch self-consistency checks of terrain-inspect --verify (docs/pyramid-format.md):
// the stored summary must be what the stored samples say, exactly, since the builder and
// this check run the same functions (io::patchBlockErrors) on the same floats.
#include "PatchChecks.h"

#include "terrain/pyramid/GlobePatchErrors.h"
#include "terrain/pyramid/PatchErrors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::inspect {

Problem patchProblem(const std::string& file, const io::PatchId& id, const std::string& what) {
    return {file, id, fmt::format("{}: patch L{} ({}, {}): {}", file, id.level, id.x, id.y, what)};
}

void checkPatchContents(const io::PyramidManifest& manifest, bool hasMask,
                        const io::PatchRecord& record, const std::string& file,
                        std::vector<Problem>& problems) {
    const io::PyramidLayout& layout = manifest.layout;
    const bool globe = manifest.globe.has_value();
    const io::PatchId& id = record.id;
    const io::PatchInfo& info = record.info;
    const auto report = [&](const std::string& what) {
        problems.push_back(patchProblem(file, id, what));
    };
    const int tile = layout.tileSamples();
    const int n = layout.patchSamples();

    for (std::size_t i = 0; i < record.heights.size(); ++i) {
        if (!std::isfinite(record.heights[i])) {
            report(fmt::format("height sample ({}, {}) of the tile is {}", i % tile, i / tile,
                               record.heights[i]));
            return;  // the other checks would only repeat it
        }
    }
    for (float v :
         {info.minHeight, info.maxHeight, info.error, info.approxError, info.quantError}) {
        if (!std::isfinite(v)) {
            report(fmt::format("patchInfo holds a non-finite value ({})", v));
            return;
        }
    }

    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (int j = 1; j <= n; ++j)
        for (int i = 1; i <= n; ++i) {
            const float h = record.heights[static_cast<std::size_t>(j * tile + i)];
            lo = std::min(lo, h);
            hi = std::max(hi, h);
        }
    if (lo != info.minHeight || hi != info.maxHeight)
        report(fmt::format("stored min/max {} / {} m, but the samples span {} / {} m",
                           info.minHeight, info.maxHeight, lo, hi));

    std::vector<io::BlockErrors> lambda(record.blockErrors.size());
    const io::GridView interior{record.heights.data() + tile + 1, n, tile};
    if (globe)
        io::globePatchBlockErrors(interior, layout.blockQuads(),
                                  id.level - io::ManifestGlobe::kLevelOffset, info.minHeight,
                                  lambda);
    else
        io::patchBlockErrors(interior, layout.blockQuads(), lambda);
    for (io::BlockErrors& e : lambda)  // as the shards store them
        for (float& bound : e) bound = io::roundUpToHalf(bound);
    for (std::size_t b = 0; b < lambda.size(); ++b) {
        if (lambda[b] != record.blockErrors[b]) {
            const int k = layout.blocksPerSide();
            report(fmt::format(
                "block ({}, {}): stored λ(1..4) = {} {} {} {} m, recomputed {} {} {} "
                "{} m",
                b % static_cast<std::size_t>(k), b / static_cast<std::size_t>(k),
                record.blockErrors[b][0], record.blockErrors[b][1], record.blockErrors[b][2],
                record.blockErrors[b][3], lambda[b][0], lambda[b][1], lambda[b][2], lambda[b][3]));
            break;  // one line per patch is enough to find it
        }
    }

    // A globe's Err(P) is measured against its sources on the stored surface, so it holds the
    // rounding already (docs/pyramid-format.md, "Lossy storage"); a planar one adds δ.
    const double atLeast =
        globe ? double(info.approxError)
              : static_cast<double>(info.approxError) + static_cast<double>(info.quantError);
    if (!(info.approxError >= 0.0f) || !(info.quantError >= 0.0f) ||
        !(static_cast<double>(info.error) >= atLeast))
        report(
            fmt::format("bounds out of order: Err(P) {} m must be ≥ Err_Appr(P) {} m{}, with "
                        "Err_Appr(P) and δ {} m ≥ 0",
                        info.error, info.approxError, globe ? "" : " + δ", info.quantError));
    // δ is the quantizer's (docs/pyramid-format.md, "Lossy storage"): at least δ_l in a lossy
    // pyramid, or 0 where it stored the patch exactly; 0 in a lossless one.
    const double halfStep = manifest.quantization
                                ? manifest.quantization->halfStep(id.level, layout.finestLevel())
                                : 0.0;
    if (info.quantError != 0.0f &&
        (!manifest.quantization || !(double(info.quantError) >= halfStep)))
        report(fmt::format("δ = {} m, but the pyramid's quantizer gives δ_l = {} m at level {}",
                           info.quantError, halfStep, id.level));
    // A globe's finest level is resampled: its Err(P) is measured against the source.
    if (!globe && id.level == layout.finestLevel() && info.approxError != 0.0f)
        report(
            fmt::format("Err_Appr(P) is {} m at the finest level (0 expected)", info.approxError));

    // Samples beyond the DEM, in finest-level coordinates, count as no-data.
    const std::int64_t step = layout.levelStep(id.level);
    const auto beyond = [&](int i, int j) {
        if (globe) return false;  // faces are whole squares; "not data" is in the mask
        return (layout.patchOriginX(id) + i) * step > layout.rasterWidth() - 1 ||
               (layout.patchOriginY(id) + j) * step > layout.rasterHeight() - 1;
    };
    std::uint32_t noData = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const bool outside = beyond(i, j);
            if (hasMask) {
                const std::uint8_t v =
                    record.valid[static_cast<std::size_t>((j + 1) * tile + (i + 1))];
                if (outside && v != 0) {
                    report(
                        fmt::format("sample ({}, {}) lies beyond the DEM but its mask is 1", i, j));
                    return;
                }
                noData += v == 0 ? 1U : 0U;
            } else {
                noData += outside ? 1U : 0U;
            }
        }
    if (noData != info.noDataSamples)
        report(fmt::format("noDataSamples is {}, but the {} counts {}", info.noDataSamples,
                           hasMask ? "mask" : "raster edge", noData));
}

}  // namespace terrain::inspect
