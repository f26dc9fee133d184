// terrain-inspect's walk over a pyramid (see PyramidInspection.h). Levels are visited from
// the finest up so that each level's Err_Appr can be checked against its children's
// (Yusov §4: Err_Appr(parent) ≥ every child's) while only one finer level is held.
#include "PyramidInspection.h"

#include <fmt/format.h>

#include <utility>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace terrain::inspect {
namespace {

constexpr float kAbsent = -1.0f;  // approxError slot of a patch that is not present

}  // namespace

Inspection inspectPyramid(io::PyramidReader& reader, const InspectOptions& options) {
    const io::PyramidLayout& layout = reader.layout();
    const io::PyramidManifest& manifest = reader.manifest();
    const std::string folder = reader.folder().string();
    Inspection result;
    result.levels.resize(static_cast<std::size_t>(layout.levelCount()));

    std::int64_t totalPatches = 0, donePatches = 0;
    for (int l = 0; l < layout.levelCount(); ++l) totalPatches += layout.patchCount(l);

    std::vector<float> childApprox;  // level l + 1, row-major, kAbsent where not present
    io::PatchRecord record;
    using Clock = std::chrono::steady_clock;
    for (int l = layout.finestLevel(); l >= 0; --l) {
        LevelSummary& summary = result.levels[static_cast<std::size_t>(l)];
        summary.level = l;
        summary.patchesX = layout.patchesX(l);
        summary.patchesY = layout.patchesY(l);
        summary.shards = layout.shardCount(l);
        std::vector<float> approx(static_cast<std::size_t>(layout.patchCount(l)), kAbsent);
        std::vector<float> errors;
        const io::ManifestLevel& listedLevel = manifest.levels[static_cast<std::size_t>(l)];
        for (std::int64_t sy = 0; sy < layout.shardsY(l); ++sy) {
            for (std::int64_t sx = 0; sx < layout.shardsX(l); ++sx) {
                const io::ShardId s{l, sx, sy};
                // A globe pyramid is sparse: only the shards it lists have files.
                if (manifest.globe &&
                    !std::binary_search(listedLevel.presentShards.begin(),
                                        listedLevel.presentShards.end(), s,
                                        [](const io::ShardId& a, const io::ShardId& b) {
                                            return std::pair(a.y, a.x) < std::pair(b.y, b.x);
                                        })) {
                    donePatches += std::int64_t{layout.shardCountX(s)} * layout.shardCountY(s);
                    continue;
                }
                const io::PatchId first{l, layout.shardFirstX(s), layout.shardFirstY(s)};
                const std::string file = reader.shardFile(first).string();
                donePatches += std::int64_t{layout.shardCountX(s)} * layout.shardCountY(s);
                if (auto info = reader.patchInfo(first); !info) {
                    ++summary.missingShards;
                    result.problems.push_back({file, std::nullopt, info.error().message});
                    continue;
                }
                // The shard is open now (fetched, for a pyramid at a URL).
                if (auto bytes = reader.shardBytes(first)) summary.bytes += bytes.value();
                for (int ty = 0; ty < layout.shardCountY(s); ++ty) {
                    for (int tx = 0; tx < layout.shardCountX(s); ++tx) {
                        const io::PatchId id{l, first.x + tx, first.y + ty};
                        auto info = reader.patchInfo(id);
                        if (!info) {  // the shard was readable a moment ago: report, go on
                            result.problems.push_back({file, id, info.error().message});
                            continue;
                        }
                        const io::PatchInfo& p = info.value();
                        if (!p.present) continue;
                        ++summary.presentPatches;
                        errors.push_back(p.error);
                        approx[static_cast<std::size_t>(id.y * summary.patchesX + id.x)] =
                            p.approxError;
                        if (l < layout.finestLevel()) {
                            float worstChild = kAbsent;
                            io::PatchId worstId{};
                            for (int cy = 0; cy < 2; ++cy)
                                for (int cx = 0; cx < 2; ++cx) {
                                    const io::PatchId child{l + 1, 2 * id.x + cx, 2 * id.y + cy};
                                    if (!layout.contains(child)) continue;
                                    const float a = childApprox[static_cast<std::size_t>(
                                        child.y * layout.patchesX(l + 1) + child.x)];
                                    const bool listedChild =
                                        (p.presentChildren >> (cy * 2 + cx)) & 1;
                                    if (manifest.globe && listedChild != (a != kAbsent))
                                        result.problems.push_back(patchProblem(
                                            file, id,
                                            fmt::format(
                                                "presentChildren says child L{} ({}, {}) is "
                                                "{}, but it is {}",
                                                child.level, child.x, child.y,
                                                listedChild ? "present" : "absent",
                                                a != kAbsent ? "present" : "absent")));
                                    if (a > worstChild) {
                                        worstChild = a;
                                        worstId = child;
                                    }
                                }
                            if (worstChild != kAbsent && !(p.approxError >= worstChild))
                                result.problems.push_back(patchProblem(
                                    file, id,
                                    fmt::format("Err_Appr {} m is below its child L{} ({}, {})'s "
                                                "{} m (bounds must nest)",
                                                p.approxError, worstId.level, worstId.x, worstId.y,
                                                worstChild)));
                        }
                        if (!options.verify) continue;
                        const auto start = Clock::now();
                        if (Status read = reader.readPatch(id, record); !read) {
                            result.problems.push_back({file, id, read.error().message});
                        } else {
                            checkPatchContents(manifest, reader.hasMask(), record, file,
                                               result.problems);
                        }
                        ++result.patchesVerified;
                        result.verifySeconds +=
                            std::chrono::duration<double>(Clock::now() - start).count();
                    }
                }
                if (options.progress)
                    options.progress(static_cast<double>(donePatches) /
                                     static_cast<double>(totalPatches));
            }
        }
        if (!errors.empty()) {
            const auto [lo, hi] = std::minmax_element(errors.begin(), errors.end());
            summary.minError = *lo;
            summary.maxError = *hi;
            auto middle = errors.begin() + static_cast<std::ptrdiff_t>(errors.size() / 2);
            std::nth_element(errors.begin(), middle, errors.end());
            summary.medianError = *middle;
        }
        const io::ManifestLevel& listed = manifest.levels[static_cast<std::size_t>(l)];
        if (summary.missingShards == 0 && listed.presentPatches != summary.presentPatches)
            result.problems.push_back(
                {folder, std::nullopt,
                 fmt::format("{}: level {}: manifest.json says {} present patches, the shards "
                             "hold {}",
                             folder, l, listed.presentPatches, summary.presentPatches)});
        if (summary.missingShards == 0 && static_cast<double>(summary.maxError) != listed.maxError)
            result.problems.push_back(
                {folder, std::nullopt,
                 fmt::format("{}: level {}: manifest.json says maxError {} m, the patches' "
                             "largest Err(P) is {} m",
                             folder, l, listed.maxError, summary.maxError)});
        childApprox = std::move(approx);
    }
    // A globe's roots are its six faces, the first level below the layout's empty top.
    const LevelSummary& root =
        result
            .levels[manifest.globe ? static_cast<std::size_t>(io::ManifestGlobe::kLevelOffset) : 0];
    if ((root.presentPatches == 1 || manifest.globe) && root.missingShards == 0 &&
        static_cast<double>(root.maxError) != manifest.statistics.rootError)
        result.problems.push_back(
            {folder, std::nullopt,
             fmt::format("{}: manifest.json says rootError {} m, the root patch's Err(P) is {} m",
                         folder, manifest.statistics.rootError, root.maxError)});
    return result;
}

}  // namespace terrain::inspect
