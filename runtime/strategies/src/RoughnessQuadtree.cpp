// RoughnessQuadtree: the blocks level by level from the finest up, σ and the height range of
// each from its samples and its four children's.
#include "terrain/runtime/RoughnessQuadtree.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace terrain::runtime {

int RoughnessQuadtree::depthFor(int width, int height) {
    int d = 1;
    while ((1 << d) + 1 < std::max(width, height)) ++d;
    return d;
}

std::size_t RoughnessQuadtree::bytesFor(int width, int height) {
    const auto side = (std::size_t{1} << depthFor(width, height)) + 1;
    const std::size_t finestBlocks = ((side - 1) / 2) * ((side - 1) / 2);
    // σ over the whole grid; the ranges' mip chain is under 4/3 of its finest level.
    return side * side * sizeof(float) + finestBlocks * 4 / 3 * sizeof(glm::vec2);
}

Result<RoughnessQuadtree> RoughnessQuadtree::build(int width, int height,
                                                   std::span<const float> heights) {
    if (width < 2 || height < 2)
        return Error{"the raster is " + std::to_string(width) + " × " + std::to_string(height) +
                     " samples; a quadtree block needs at least 2 × 2"};
    if (heights.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
        return Error{"the height array does not hold width × height samples"};
    RoughnessQuadtree tree;
    tree.m_width = width;
    tree.m_height = height;
    tree.m_depth = depthFor(width, height);
    tree.m_side = (1 << tree.m_depth) + 1;
    const int n = tree.m_side;
    tree.m_roughness.assign(static_cast<std::size_t>(n) * n, 0.0f);
    tree.m_heightRange.resize(static_cast<std::size_t>(tree.m_depth));

    // Samples beyond the raster repeat its edge: they only enter blocks that overhang it,
    // which are forced to split and never drawn whole.
    const auto at = [&](int x, int y) {
        x = std::min(x, width - 1);
        y = std::min(y, height - 1);
        return heights[static_cast<std::size_t>(y) * width + x];
    };
    for (int level = 0; level < tree.m_depth; ++level) {
        const int h = 1 << level;
        const int blocks = tree.blocksPerSide(level);
        auto& range = tree.m_heightRange[static_cast<std::size_t>(level)];
        range.resize(static_cast<std::size_t>(blocks) * blocks);
        for (int by = 0; by < blocks; ++by) {
            for (int bx = 0; bx < blocks; ++bx) {
                const int cx = h + 2 * h * bx, cy = h + 2 * h * by;
                const int x0 = cx - h, y0 = cy - h, x1 = cx + h, y1 = cy + h;
                // Fig. 2: the five midpoints against the block's own surface.
                const float c00 = at(x0, y0), c10 = at(x1, y0), c01 = at(x0, y1), c11 = at(x1, y1);
                float sigma = std::max({std::abs(at(cx, cy) - 0.5f * (c00 + c11)),
                                        std::abs(at(cx, y0) - 0.5f * (c00 + c10)),
                                        std::abs(at(cx, y1) - 0.5f * (c01 + c11)),
                                        std::abs(at(x0, cy) - 0.5f * (c00 + c01)),
                                        std::abs(at(x1, cy) - 0.5f * (c10 + c11))});
                glm::vec2 minMax;
                if (level == 0) {
                    minMax = {c00, c00};
                    for (int y = y0; y <= y1; ++y)
                        for (int x = x0; x <= x1; ++x)
                            minMax = {std::min(minMax.x, at(x, y)), std::max(minMax.y, at(x, y))};
                } else {
                    // Eq. 3 / Fig. 4: at least twice every child's roughness.
                    const auto& finer = tree.m_heightRange[static_cast<std::size_t>(level - 1)];
                    const int finerBlocks = tree.blocksPerSide(level - 1);
                    minMax = {finer[static_cast<std::size_t>(2 * by) * finerBlocks + 2 * bx].x,
                              finer[static_cast<std::size_t>(2 * by) * finerBlocks + 2 * bx].y};
                    for (int child = 0; child < 4; ++child) {
                        const int fx = 2 * bx + (child & 1), fy = 2 * by + (child >> 1);
                        const glm::vec2 r = finer[static_cast<std::size_t>(fy) * finerBlocks + fx];
                        minMax = {std::min(minMax.x, r.x), std::max(minMax.y, r.y)};
                        const int ccx = cx + ((child & 1) ? h / 2 : -h / 2);
                        const int ccy = cy + ((child >> 1) ? h / 2 : -h / 2);
                        sigma = std::max(sigma, 2.0f * tree.roughnessAt(ccx, ccy));
                    }
                }
                const bool overhangs = x1 > width - 1 || y1 > height - 1;
                if (overhangs) sigma = kForceSplit;
                tree.m_roughness[static_cast<std::size_t>(cy) * n + cx] =
                    std::min(sigma, kForceSplit);
                range[static_cast<std::size_t>(by) * blocks + bx] = minMax;
            }
        }
    }
    return tree;
}

}  // namespace terrain::runtime
