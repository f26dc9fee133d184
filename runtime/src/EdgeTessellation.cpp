// EdgeTessellation: the edge rule of terrain.tesc in double, edge by edge as the shader
// does it (each block decides its four edges; a shared edge from the same inputs).
#include "terrain/runtime/EdgeTessellation.h"

#include "terrain/io/Assert.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {
namespace {

constexpr std::array<glm::ivec2, 4> kEdgeNeighbour{{{-1, 0}, {0, -1}, {1, 0}, {0, 1}}};
// Ends of each edge in block corners (terrainEdgeEnds in terrain_patches.glsl).
constexpr std::array<glm::ivec2, 4> kEdgeStart{{{0, 0}, {0, 0}, {1, 0}, {0, 1}}};
constexpr std::array<glm::ivec2, 4> kEdgeEnd{{{0, 1}, {1, 0}, {1, 1}, {1, 1}}};

}  // namespace

double projectedSegmentPx(const glm::dmat4& relativeViewProjection, const glm::dvec2& viewportPx,
                          const glm::dvec3& centreM, const double lengthM) {
    if (lengthM <= 0.0) return 0.0;  // no error: nothing to see, even behind the camera
    const glm::dvec3 halfUp{0.0, 0.0, 0.5 * lengthM};
    const glm::dvec4 lo = relativeViewProjection * glm::dvec4(centreM - halfUp, 1.0);
    const glm::dvec4 hi = relativeViewProjection * glm::dvec4(centreM + halfUp, 1.0);
    if (lo.z > lo.w || hi.z > hi.w) return std::numeric_limits<double>::infinity();
    const glm::dvec2 deltaPx = (glm::dvec2(hi) / hi.w - glm::dvec2(lo) / lo.w) * (0.5 * viewportPx);
    return std::hypot(deltaPx.x, deltaPx.y);
}

int edgeSimplification(std::span<const double, io::kMaxSimplification> projectedPx,
                       double errorPx) {
    int d = 0;
    for (int k = 1; k <= io::kMaxSimplification; ++k) {
        if (projectedPx[static_cast<std::size_t>(k - 1)] < errorPx) d = k;
    }
    return d;
}

int tessFactorOf(int blockQuads, int d) { return std::max(1, blockQuads >> d); }

bool blockDiscarded(const Camera& camera, const TerrainGeometry& geometry, const io::PatchId& id,
                    const io::PatchInfo& info, glm::ivec2 block, double dropM) {
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
    const glm::dvec2 nw =
        geometry.worldOfSample(column + block.x * quads * step, row + block.y * quads * step);
    const glm::dvec2 se = geometry.worldOfSample(column + (block.x + 1) * quads * step,
                                                 row + (block.y + 1) * quads * step);
    const Aabb box{.min = {nw.x, se.y, static_cast<double>(info.minHeight) - dropM},
                   .max = {se.x, nw.y, static_cast<double>(info.maxHeight)}};
    return !camera.frustum().intersects(box);
}

std::vector<BlockFactors> patchBlockFactors(const Camera& camera, const TerrainGeometry& geometry,
                                            const io::PatchRecord& record, double errorPx) {
    const io::PyramidLayout& layout = geometry.layout();
    const int blocks = layout.blocksPerSide();
    const int quads = layout.blockQuads();
    const int tile = layout.tileSamples();
    TERRAIN_ASSERT(record.blockErrors.size() == static_cast<std::size_t>(blocks * blocks));
    TERRAIN_ASSERT(record.heights.size() == static_cast<std::size_t>(tile * tile));
    const double patchErrorM = static_cast<double>(record.info.error);
    const std::int64_t step = layout.levelStep(record.id.level);
    const double originColumn = static_cast<double>(layout.patchOriginX(record.id) * step);
    const double originRow = static_cast<double>(layout.patchOriginY(record.id) * step);
    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    const glm::dvec2 viewportPx{camera.viewportWidth, camera.viewportHeight};

    // Λ(d) = λ(d) + Err(P) (Yusov §5, "Tessellation Blocks").
    const auto blockErrorM = [&](glm::ivec2 block, int d) {
        const io::BlockErrors& lambda =
            record.blockErrors[static_cast<std::size_t>(block.y * blocks + block.x)];
        return static_cast<double>(lambda[static_cast<std::size_t>(d - 1)]) + patchErrorM;
    };

    std::vector<BlockFactors> out(static_cast<std::size_t>(blocks * blocks));
    for (int by = 0; by < blocks; ++by) {
        for (int bx = 0; bx < blocks; ++bx) {
            const glm::ivec2 block{bx, by};
            BlockFactors& f = out[static_cast<std::size_t>(by * blocks + bx)];
            for (std::size_t e = 0; e < 4; ++e) {
                // e_c: the edge's centre sample, at its height from the patch's heights.
                const glm::ivec2 centre =
                    block * quads + (kEdgeStart[e] + kEdgeEnd[e]) * (quads / 2);
                const double heightM = static_cast<double>(
                    record.heights[static_cast<std::size_t>((centre.y + 1) * tile + centre.x + 1)]);
                const glm::dvec2 world =
                    geometry.worldOfSample(originColumn + centre.x * static_cast<double>(step),
                                           originRow + centre.y * static_cast<double>(step));
                const glm::dvec3 centreM{world.x - camera.position.x, world.y - camera.position.y,
                                         heightM - camera.position.z};
                // Λ_ec(d): the max over the patch's blocks sharing the edge (Yusov §5).
                const glm::ivec2 other = block + kEdgeNeighbour[e];
                const bool shared =
                    other.x >= 0 && other.y >= 0 && other.x < blocks && other.y < blocks;
                std::array<double, io::kMaxSimplification> edgeErrorM{};
                for (int d = 1; d <= io::kMaxSimplification; ++d) {
                    double lambda = blockErrorM(block, d);
                    if (shared) lambda = std::max(lambda, blockErrorM(other, d));
                    edgeErrorM[static_cast<std::size_t>(d - 1)] = lambda;
                    f.projectedPx[e][static_cast<std::size_t>(d - 1)] =
                        projectedSegmentPx(viewProjection, viewportPx, centreM, lambda);
                }
                const int d = edgeSimplification(f.projectedPx[e], errorPx);
                f.simplification[e] = d;
                f.outer[e] = tessFactorOf(quads, d);
                f.edgeErrorM[e] =
                    d == 0 ? patchErrorM : edgeErrorM[static_cast<std::size_t>(d - 1)];
            }
            const int inner = *std::min_element(f.outer.begin(), f.outer.end());
            f.inner = {inner, inner};
            f.culled = blockDiscarded(camera, geometry, record.id, record.info, block, 0.0);
        }
    }
    return out;
}

}  // namespace terrain::runtime
