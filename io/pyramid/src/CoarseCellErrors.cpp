// CoarseCellErrors: the block-corner grid's simplification error plus the blocks' own λ at
// factor 1, cell by cell (the header derives the bound).
#include "terrain/pyramid/CoarseCellErrors.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <bit>

namespace terrain::io {

int coarseCellLevels(int patchQuads, int blockQuads) {
    if (blockQuads < 2 || !std::has_single_bit(static_cast<unsigned>(blockQuads))) return 0;
    if (std::countr_zero(static_cast<unsigned>(blockQuads)) > kMaxSimplification) return 0;
    TERRAIN_ASSERT(patchQuads % blockQuads == 0);
    const auto blocks = static_cast<unsigned>(patchQuads / blockQuads);
    return std::countr_zero(std::bit_floor(blocks));
}

int coarseCellOffset(int blocksPerSide, int k) {
    int offset = 0;
    for (int j = 1; j < k; ++j) offset += (blocksPerSide >> j) * (blocksPerSide >> j);
    return offset;
}

int coarseCellCount(int patchQuads, int blockQuads) {
    const int levels = coarseCellLevels(patchQuads, blockQuads);
    return levels == 0 ? 0 : coarseCellOffset(patchQuads / blockQuads, levels + 1);
}

void coarseCellErrors(const GridView& patch, int blockQuads,
                      std::span<const BlockErrors> blockErrors, std::span<float> cornerScratch,
                      std::span<float> out) {
    const int patchQuads = patch.side - 1;
    const int levels = coarseCellLevels(patchQuads, blockQuads);
    TERRAIN_ASSERT(out.size() == static_cast<std::size_t>(coarseCellCount(patchQuads, blockQuads)));
    if (levels == 0) return;
    const int blocks = patchQuads / blockQuads;
    const int cornerSide = blocks + 1;
    TERRAIN_ASSERT(blockErrors.size() == static_cast<std::size_t>(blocks) * blocks);
    TERRAIN_ASSERT(cornerScratch.size() >= static_cast<std::size_t>(cornerSide) * cornerSide);
    for (int y = 0; y < cornerSide; ++y)
        for (int x = 0; x < cornerSide; ++x)
            cornerScratch[static_cast<std::size_t>(y * cornerSide + x)] =
                patch.at(x * blockQuads, y * blockQuads);
    const GridView corners{cornerScratch.data(), cornerSide, cornerSide};
    // λ(d₁): the factor-1 level of a block (tessellation factor blockQuads >> d₁ = 1).
    const auto factorOne =
        static_cast<std::size_t>(std::countr_zero(static_cast<unsigned>(blockQuads)) - 1);

    std::size_t next = 0;
    for (int k = 1; k <= levels; ++k) {
        const int cellBlocks = 1 << k;
        for (int cy = 0; cy + cellBlocks <= blocks; cy += cellBlocks) {
            for (int cx = 0; cx + cellBlocks <= blocks; cx += cellBlocks) {
                float lambda = 0.0f;
                for (int by = cy; by < cy + cellBlocks; ++by)
                    for (int bx = cx; bx < cx + cellBlocks; ++bx)
                        lambda = std::max(
                            lambda,
                            blockErrors[static_cast<std::size_t>(by * blocks + bx)][factorOne]);
                const double bound = static_cast<double>(simplificationError(
                                         corners, cx, cy, cellBlocks, cellBlocks)) +
                                     static_cast<double>(lambda);
                out[next++] = roundUpToFloat(bound);
            }
        }
    }
    TERRAIN_ASSERT(next == out.size());
}

std::vector<float> coarseCellErrors(const GridView& patch, int blockQuads,
                                    std::span<const BlockErrors> blockErrors) {
    std::vector<float> out(static_cast<std::size_t>(coarseCellCount(patch.side - 1, blockQuads)));
    if (out.empty()) return out;
    const int cornerSide = (patch.side - 1) / blockQuads + 1;
    std::vector<float> scratch(static_cast<std::size_t>(cornerSide) * cornerSide);
    coarseCellErrors(patch, blockQuads, blockErrors, scratch, out);
    return out;
}

}  // namespace terrain::io
