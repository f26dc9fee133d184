// EdgeTessellation: the edge rule of terrain.tesc in double, edge by edge as the shader
// does it (each block decides its four edges; a shared edge from the same inputs).
#include "terrain/runtime/EdgeTessellation.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/BlockHeightRanges.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

namespace terrain::runtime {
namespace {

constexpr std::array<glm::ivec2, 4> kEdgeNeighbour{{{-1, 0}, {0, -1}, {1, 0}, {0, 1}}};

}  // namespace

Aabb blocksWorldBox(const TerrainGeometry& geometry, const io::PatchId& id, glm::ivec2 first,
                    glm::ivec2 last, double lowM, double highM) {
    const io::PyramidLayout& layout = geometry.layout();
    const double step = static_cast<double>(layout.levelStep(id.level));
    const double quads = static_cast<double>(layout.blockQuads());
    const double column = static_cast<double>(layout.patchOriginX(id)) * step;
    const double row = static_cast<double>(layout.patchOriginY(id)) * step;
    // Rows run south: the north-west corner has the larger y.
    const glm::dvec2 nw =
        geometry.worldOfSample(column + first.x * quads * step, row + first.y * quads * step);
    const glm::dvec2 se = geometry.worldOfSample(column + (last.x + 1) * quads * step,
                                                 row + (last.y + 1) * quads * step);
    return {.min = {nw.x, se.y, lowM}, .max = {se.x, nw.y, highM}};
}

double verticalErrorPxPerM(const glm::dmat4& relativeViewProjection, const glm::dvec2& viewportPx,
                           const Aabb& box) {
    const glm::dmat4& m = relativeViewProjection;
    const double nearM = m[3][2];  // Camera::projection: z_clip = near, the rotation adds none
    double depthMin = std::numeric_limits<double>::infinity();
    glm::dvec2 ndcLo{std::numeric_limits<double>::infinity()};
    glm::dvec2 ndcHi{-std::numeric_limits<double>::infinity()};
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 corner{(i & 1) != 0 ? box.max.x : box.min.x,
                                (i & 2) != 0 ? box.max.y : box.min.y,
                                (i & 4) != 0 ? box.max.z : box.min.z};
        const glm::dvec4 clip = m * glm::dvec4(corner, 1.0);
        depthMin = std::min(depthMin, clip.w);
        const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
        ndcLo = glm::min(ndcLo, ndc);
        ndcHi = glm::max(ndcHi, ndc);
    }
    if (!(depthMin > 0.0)) {
        // The box reaches behind the camera: its projection is unbounded; the screen is not.
        ndcLo = glm::dvec2(-1.0);
        ndcHi = glm::dvec2(1.0);
    }
    ndcLo = glm::clamp(ndcLo, -1.0, 1.0);
    ndcHi = glm::clamp(ndcHi, -1.0, 1.0);
    const glm::dvec4 a = m[2];  // the clip-space image of e_z
    double largest = 0.0;
    for (const double x : {ndcLo.x, ndcHi.x}) {
        for (const double y : {ndcLo.y, ndcHi.y}) {
            largest = std::max(largest, std::hypot((a.x - x * a.w) * 0.5 * viewportPx.x,
                                                   (a.y - y * a.w) * 0.5 * viewportPx.y));
        }
    }
    // A point in the frustum has |p| ≤ w · √(1 + tan²x + tan²y), and the rows of the
    // projection's x and y are the camera's right and up over tan x and tan y.
    const glm::dvec3 rowX{m[0].x, m[1].x, m[2].x};
    const glm::dvec3 rowY{m[0].y, m[1].y, m[2].y};
    const double diagonal =
        std::sqrt(1.0 + 1.0 / glm::dot(rowX, rowX) + 1.0 / glm::dot(rowY, rowY));
    const double depthOfDistance = distanceToBox(glm::dvec3(0.0), box) / diagonal;
    return largest / std::max({depthMin, depthOfDistance, nearM});
}

// The control stage's steps (terrain.tesc), mirrored.
namespace {

/// Yusov §5: d = argmax_d proj(d) < ε over d = 1..4; 0 when no d qualifies.
int edgeSimplification(std::span<const double, io::kMaxSimplification> projectedPx,
                       double errorPx) {
    int d = 0;
    for (int k = 1; k <= io::kMaxSimplification; ++k) {
        if (projectedPx[static_cast<std::size_t>(k - 1)] < errorPx) d = k;
    }
    return d;
}

/// The edge factor of simplification d: max(1, blockQuads >> d), a power of two dividing
/// blockQuads (a simplification coarser than the block keeps its corners: 1).
int tessFactorOf(int blockQuads, int d) { return std::max(1, blockQuads >> d); }

/// Whether the control stage may discard `block` of patch `id`: it lies wholly beyond the
/// DEM's extent (a patch overhanging its edge), or its box — the block's footprint, its
/// height range `range` (terrain_patches.glsl, blocksHeightRangeM), reaching `dropM` further
/// down (a skirt's drop; 0 for the block) — lies outside `camera`'s frustum. In double,
/// without the control stage's float margin, so the GPU never discards a block this keeps.
bool blockDiscarded(const Camera& camera, const TerrainGeometry& geometry, const io::PatchId& id,
                    io::HeightRange range, glm::ivec2 block, double dropM) {
    const io::PyramidLayout& layout = geometry.layout();
    const double step = static_cast<double>(layout.levelStep(id.level));
    const double quads = static_cast<double>(layout.blockQuads());
    const double column = static_cast<double>(layout.patchOriginX(id)) * step;
    const double row = static_cast<double>(layout.patchOriginY(id)) * step;
    const double firstColumn = column + block.x * quads * step;
    const double firstRow = row + block.y * quads * step;
    if (firstColumn > static_cast<double>(layout.rasterWidth() - 1) ||
        firstRow > static_cast<double>(layout.rasterHeight() - 1)) {
        return true;  // wholly beyond the DEM
    }
    return !camera.frustum().intersects(blocksWorldBox(geometry, id, block, block,
                                                       static_cast<double>(range.low) - dropM,
                                                       static_cast<double>(range.high)));
}

}  // namespace

std::vector<BlockFactors> patchBlockFactors(const Camera& camera, const TerrainGeometry& geometry,
                                            const io::PatchRecord& record, double errorPx) {
    const io::PyramidLayout& layout = geometry.layout();
    const int blocks = layout.blocksPerSide();
    const int quads = layout.blockQuads();
    TERRAIN_ASSERT(record.blockErrors.size() == static_cast<std::size_t>(blocks * blocks));
    const double patchErrorM = static_cast<double>(record.info.error);
    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    const glm::dvec2 viewportPx{camera.viewportWidth, camera.viewportHeight};

    // Λ(d) = λ(d) + Err(P) (Yusov §5, "Tessellation Blocks").
    const auto blockErrorM = [&](glm::ivec2 block, int d) {
        const io::BlockErrors& lambda =
            record.blockErrors[static_cast<std::size_t>(block.y * blocks + block.x)];
        return static_cast<double>(lambda[static_cast<std::size_t>(d - 1)]) + patchErrorM;
    };

    // Each block's own heights, as the GPU pool uploads them for the control stage.
    const int tileSamples = layout.tileSamples();
    const int patchSamples = tileSamples - 2;
    TERRAIN_ASSERT(record.heights.size() == static_cast<std::size_t>(tileSamples * tileSamples));
    std::vector<io::HeightRange> ranges(static_cast<std::size_t>(blocks * blocks));
    io::blockHeightRanges(
        io::GridView{record.heights.data() + tileSamples + 1, patchSamples, tileSamples}, quads,
        {record.info.minHeight, record.info.maxHeight}, ranges);
    const auto rangeOf = [&](glm::ivec2 block) {
        return ranges[static_cast<std::size_t>(block.y * blocks + block.x)];
    };

    // The camera-relative box of blocks first..last (inclusive, one block or an edge's
    // two): their footprint, and their heights widened by Err(P), since the full-resolution
    // surface may lie that far beyond the patch's samples, and an error's segment ends on it.
    const auto edgeBoxM = [&](glm::ivec2 first, glm::ivec2 last) {
        const io::HeightRange a = rangeOf(first), b = rangeOf(last);
        const double lowM = static_cast<double>(std::min(a.low, b.low)) - patchErrorM;
        const double highM = static_cast<double>(std::max(a.high, b.high)) + patchErrorM;
        const Aabb world = blocksWorldBox(geometry, record.id, first, last, lowM, highM);
        return Aabb{.min = world.min - camera.position, .max = world.max - camera.position};
    };

    std::vector<BlockFactors> out(static_cast<std::size_t>(blocks * blocks));
    for (int by = 0; by < blocks; ++by) {
        for (int bx = 0; bx < blocks; ++bx) {
            const glm::ivec2 block{bx, by};
            BlockFactors& f = out[static_cast<std::size_t>(by * blocks + bx)];
            for (std::size_t e = 0; e < 4; ++e) {
                // Λ_ec(d): the max over the patch's blocks sharing the edge (Yusov §5), and
                // the box of those blocks, where the edge's d must hold.
                const glm::ivec2 other = block + kEdgeNeighbour[e];
                const bool shared =
                    other.x >= 0 && other.y >= 0 && other.x < blocks && other.y < blocks;
                const glm::ivec2 first = shared ? glm::min(block, other) : block;
                const glm::ivec2 last = shared ? glm::max(block, other) : block;
                const double pxPerM =
                    verticalErrorPxPerM(viewProjection, viewportPx, edgeBoxM(first, last));
                std::array<double, io::kMaxSimplification> edgeErrorM{};
                for (int d = 1; d <= io::kMaxSimplification; ++d) {
                    double lambda = blockErrorM(block, d);
                    if (shared) lambda = std::max(lambda, blockErrorM(other, d));
                    edgeErrorM[static_cast<std::size_t>(d - 1)] = lambda;
                    // No error: nothing to see, wherever the box lies.
                    f.projectedPx[e][static_cast<std::size_t>(d - 1)] =
                        lambda > 0.0 ? lambda * pxPerM : 0.0;
                }
                const int d = edgeSimplification(f.projectedPx[e], errorPx);
                f.simplification[e] = d;
                f.outer[e] = tessFactorOf(quads, d);
                f.edgeErrorM[e] =
                    d == 0 ? patchErrorM : edgeErrorM[static_cast<std::size_t>(d - 1)];
            }
            // The inner factor: the coarsest edge's, or coarser where the block's own Λ(d)
            // over its own box allows (terrain.tesc, blockInnerFactor, says why it holds).
            const int coarsestEdge = *std::min_element(f.outer.begin(), f.outer.end());
            const double ownPxPerM =
                verticalErrorPxPerM(viewProjection, viewportPx, edgeBoxM(block, block));
            int inner = coarsestEdge;
            for (int d = 1; d <= io::kMaxSimplification; ++d) {
                const double lambda = blockErrorM(block, d);
                const double projected = lambda > 0.0 ? lambda * ownPxPerM : 0.0;
                f.innerProjectedPx[static_cast<std::size_t>(d - 1)] = projected;
                const int factor = tessFactorOf(quads, d);
                if (factor < inner && projected < errorPx) inner = factor;
            }
            f.inner = {inner, inner};
            f.culled = blockDiscarded(camera, geometry, record.id, rangeOf(block), block, 0.0);
        }
    }
    return out;
}

}  // namespace terrain::runtime
