// Tiny pyramids for tests, written shard by shard with ShardWriter and a manifest, without
// the builder: the heights are a smooth deterministic function of the DEM sample plus
// seeded noise, so error bounds and block errors are real and nest as the spec says.
#pragma once

#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/ShardWriter.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace terrain::test {

struct TinyPyramidOptions {
    std::int64_t width = 37;  ///< DEM samples
    std::int64_t height = 29;
    int patchSamples = 9;
    int blockQuads = 4;
    int shardPatches = 2;
    bool withNoData = false;  ///< a hole of no-data samples near the DEM's centre; V mask
    std::uint64_t seed = 1;
    /// Patches to leave absent (not written); by default none.
    std::function<bool(const io::PatchId&)> absent;
};

/// Deterministic heights: smooth hills plus hashed noise of ±2 m (exact multiples of 1/64).
inline float tinyHeight(std::uint64_t seed, std::int64_t x, std::int64_t y) {
    std::uint64_t h = seed * 0x9E3779B97F4A7C15ULL ^
                      static_cast<std::uint64_t>(x) * 0xBF58476D1CE4E5B9ULL ^
                      static_cast<std::uint64_t>(y) * 0x94D049BB133111EBULL;
    h ^= h >> 31U;
    h *= 0xD6E8FEB86659FD93ULL;
    h ^= h >> 32U;
    const double noise = static_cast<double>(h % 257) / 64.0 - 2.0;
    const double hills =
        100.0 * std::sin(static_cast<double>(x) * 0.21) * std::cos(static_cast<double>(y) * 0.17) +
        0.5 * static_cast<double>(x);
    return static_cast<float>(std::round((hills + noise) * 64.0) / 64.0);
}

/// A tiny pyramid's samples at any level, with the spec's clamping beyond the DEM.
class TinyPyramid {
public:
    TinyPyramid(const io::PyramidLayout& layout, TinyPyramidOptions options)
        : m_layout(layout), m_options(std::move(options)) {}

    const io::PyramidLayout& layout() const { return m_layout; }
    const TinyPyramidOptions& options() const { return m_options; }

    bool isHole(std::int64_t x, std::int64_t y) const {
        if (!m_options.withNoData) return false;
        const std::int64_t cx = m_options.width / 2, cy = m_options.height / 2;
        return std::abs(x - cx) <= 2 && std::abs(y - cy) <= 1;
    }

    /// Level sample (i, j) of `level`: DEM sample (i·step, j·step), clamped into the DEM.
    float levelSample(int level, std::int64_t i, std::int64_t j) const {
        const std::int64_t step = m_layout.levelStep(level);
        return tinyHeight(m_options.seed,
                          std::clamp<std::int64_t>(i * step, 0, m_options.width - 1),
                          std::clamp<std::int64_t>(j * step, 0, m_options.height - 1));
    }

    /// 1 valid, 0 filled or beyond the DEM.
    std::uint8_t levelValid(int level, std::int64_t i, std::int64_t j) const {
        const std::int64_t step = m_layout.levelStep(level);
        const std::int64_t x = i * step, y = j * step;
        if (x < 0 || y < 0 || x >= m_options.width || y >= m_options.height) return 0;
        return isHole(x, y) ? 0 : 1;
    }

    bool isAbsent(const io::PatchId& id) const { return m_options.absent && m_options.absent(id); }

    /// Err_Appr of a patch (Yusov §4): 0 at the finest level, else Err_Int of its joined
    /// children plus the largest of theirs.
    float approxError(const io::PatchId& id) {
        if (id.level == m_layout.finestLevel()) return 0.0f;
        const auto key = std::make_tuple(id.level, id.x, id.y);
        if (const auto it = m_approx.find(key); it != m_approx.end()) return it->second;
        const int quads = m_layout.patchQuads();
        const int side = 2 * quads + 1;
        std::vector<float> joined(static_cast<std::size_t>(side) * static_cast<std::size_t>(side));
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i)
                joined[static_cast<std::size_t>(j * side + i)] =
                    levelSample(id.level + 1, 2 * id.x * quads + i, 2 * id.y * quads + j);
        double worst = io::interpolationError({joined.data(), side, side});
        float children = 0.0f;
        for (int cy = 0; cy < 2; ++cy)
            for (int cx = 0; cx < 2; ++cx) {
                const io::PatchId child{id.level + 1, 2 * id.x + cx, 2 * id.y + cy};
                if (m_layout.contains(child) && !isAbsent(child))
                    children = std::max(children, approxError(child));
            }
        worst += children;
        auto bound = static_cast<float>(worst);
        if (static_cast<double>(bound) < worst)
            bound = std::nextafter(bound, std::numeric_limits<float>::infinity());
        m_approx[key] = bound;
        return bound;
    }

    io::PatchRecord patch(const io::PatchId& id) {
        const int tile = m_layout.tileSamples();
        const int n = m_layout.patchSamples();
        io::PatchRecord r;
        r.id = id;
        r.heights.resize(static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile));
        if (m_options.withNoData) r.valid.resize(r.heights.size());
        const std::int64_t x0 = m_layout.patchOriginX(id) - 1, y0 = m_layout.patchOriginY(id) - 1;
        for (int j = 0; j < tile; ++j)
            for (int i = 0; i < tile; ++i) {
                const auto k = static_cast<std::size_t>(j * tile + i);
                r.heights[k] = levelSample(id.level, x0 + i, y0 + j);
                if (m_options.withNoData) r.valid[k] = levelValid(id.level, x0 + i, y0 + j);
            }
        // Overhanging samples count as no-data whether or not the pyramid stores a mask.
        std::vector<std::uint8_t> valid(r.heights.size());
        for (int j = 0; j < tile; ++j)
            for (int i = 0; i < tile; ++i)
                valid[static_cast<std::size_t>(j * tile + i)] =
                    levelValid(id.level, x0 + i, y0 + j);
        r.info.present = true;
        io::summariseDrawnSamples(m_layout, r.heights, valid, r.info);
        r.info.approxError = approxError(id);
        r.info.quantError = 0.0f;
        r.info.error = r.info.approxError;
        const int blocks = m_layout.blocksPerSide();
        r.blockErrors.resize(static_cast<std::size_t>(blocks) * static_cast<std::size_t>(blocks));
        io::patchBlockErrors({r.heights.data() + tile + 1, n, tile}, m_layout.blockQuads(),
                             r.blockErrors);
        return r;
    }

    /// Writes every shard and the manifest into `dir` (created). Returns the manifest.
    Result<io::PyramidManifest> write(const std::filesystem::path& dir) {
        std::filesystem::create_directories(dir);
        io::PyramidManifest manifest = io::PyramidManifest::forLayout(m_layout);
        manifest.noData.present = m_options.withNoData;
        manifest.source = {{"tiny-pyramid"}, "test", "float32"};
        manifest.build = {"TinyPyramid.h", "0", 0.0};
        for (int l = 0; l < m_layout.levelCount(); ++l) {
            std::int64_t present = 0;
            double maxError = 0.0;
            for (std::int64_t sy = 0; sy < m_layout.shardsY(l); ++sy)
                for (std::int64_t sx = 0; sx < m_layout.shardsX(l); ++sx) {
                    const io::ShardId s{l, sx, sy};
                    auto writer = io::ShardWriter::create(dir / m_layout.shardPath(s), m_layout, s,
                                                          m_options.withNoData);
                    if (!writer) return writer.error();
                    for (int ty = 0; ty < m_layout.shardCountY(s); ++ty)
                        for (int tx = 0; tx < m_layout.shardCountX(s); ++tx) {
                            const io::PatchId id{l, m_layout.shardFirstX(s) + tx,
                                                 m_layout.shardFirstY(s) + ty};
                            if (isAbsent(id)) continue;
                            const io::PatchRecord r = patch(id);
                            ++present;
                            maxError = std::max(maxError, static_cast<double>(r.info.error));
                            if (Status ok = writer.value().writePatch(r); !ok) return ok.error();
                        }
                    if (Status ok = writer.value().finish(); !ok) return ok.error();
                }
            manifest.levels[static_cast<std::size_t>(l)].presentPatches = present;
            manifest.levels[static_cast<std::size_t>(l)].maxError = maxError;
        }
        std::int64_t valid = 0;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (std::int64_t y = 0; y < m_options.height; ++y)
            for (std::int64_t x = 0; x < m_options.width; ++x) {
                if (isHole(x, y)) continue;
                ++valid;
                lo = std::min(lo, static_cast<double>(tinyHeight(m_options.seed, x, y)));
                hi = std::max(hi, static_cast<double>(tinyHeight(m_options.seed, x, y)));
            }
        manifest.noData.samples = m_options.width * m_options.height - valid;
        manifest.statistics = {lo, hi, valid, manifest.levels[0].maxError};
        if (Status ok = io::writeManifest(dir, manifest); !ok) return ok.error();
        return manifest;
    }

private:
    io::PyramidLayout m_layout;
    TinyPyramidOptions m_options;
    std::map<std::tuple<int, std::int64_t, std::int64_t>, float> m_approx;
};

/// Creates the layout from `options` and writes the pyramid into `dir`.
inline Result<io::PyramidManifest> writeTinyPyramid(const std::filesystem::path& dir,
                                                    const TinyPyramidOptions& options) {
    auto layout = io::PyramidLayout::create(options.width, options.height, options.patchSamples,
                                            options.blockQuads, options.shardPatches);
    if (!layout) return layout.error();
    TinyPyramid pyramid(layout.value(), options);
    return pyramid.write(dir);
}

}  // namespace terrain::test
