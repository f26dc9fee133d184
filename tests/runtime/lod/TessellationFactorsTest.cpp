// The terrain's tessellation control stage against its CPU reference (EdgeTessellation.h,
// Yusov & Shevtsov 2011, §5): the real program, built with TERRAIN_DEBUG_TESS_FACTORS,
// records every (instance, primitive)'s factors while it draws every patch of the streaming
// test pyramid from many camera poses. Factors must equal the model's except where a
// projected edge error lies within a tiny relative tolerance of ε (float against double);
// shared block edges agree bit for bit, factors are powers of two ≤ blockQuads, inner is
// the CPU's (never finer than the coarsest edge, coarser where the block's own error
// allows), and each skirt follows its block edge.
#include "GlTestFixture.h"
#include "StreamingTestPyramid.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/pyramid/CoarseCellErrors.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/CoarseCells.h"
#include "terrain/runtime/EdgeTessellation.h"
#include "terrain/runtime/PlaneSurface.h"
#include "terrain/runtime/SkirtDepth.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace terrain::test {
namespace {

// ε of a draw whose factors are fixed (TerrainStyle::fixedTessFactor): it decides nothing.
constexpr double kFixedFactorErrorPx = 2.0;

using runtime::BlockFactors;
using runtime::Camera;
using runtime::PatchDraw;
using runtime::RecordedTessFactors;

// float against double: a projected length this close to ε (relative) may fall either way.
constexpr double kBorderlineRelative = 1e-4;

struct Pose {
    std::string name;
    Camera camera;
    double errorPx = 2.0;
};

/// Every present patch of the streaming test pyramid, uploaded to a pool of its own.
struct Scene {
    io::PyramidManifest manifest;
    std::unique_ptr<runtime::PlaneSurface> surface;  // the draws' (the renderers hold it)
    std::vector<io::PatchRecord> records;
    cache::GpuTilePool pool;
    std::vector<PatchDraw> draws;  // one per record, same order
};

Scene loadScene() {
    auto reader = io::PyramidReader::open(streamingTestPyramid());
    EXPECT_TRUE(reader) << reader.error().message;
    Scene scene;
    scene.manifest = reader.value().manifest();
    scene.surface = std::make_unique<runtime::PlaneSurface>(scene.manifest);
    const io::PyramidLayout& layout = scene.manifest.layout;
    for (int level = 0; level < layout.levelCount(); ++level) {
        for (std::int64_t y = 0; y < layout.patchesY(level); ++y) {
            for (std::int64_t x = 0; x < layout.patchesX(level); ++x) {
                auto record = reader.value().readPatch({level, x, y});
                EXPECT_TRUE(record) << record.error().message;
                if (record) scene.records.push_back(std::move(record).value());
            }
        }
    }
    const std::size_t bytes = cache::GpuTilePool::bytesPerLayer(layout) * scene.records.size();
    auto pool = cache::GpuTilePool::create(
        layout, {.budgetBytes = bytes, .uploadBudgetBytesPerFrame = bytes, .ringBytes = 0});
    EXPECT_TRUE(pool) << pool.error().message;
    scene.pool = std::move(pool).value();
    scene.pool.beginFrame();
    for (const io::PatchRecord& record : scene.records) {
        const std::optional<int> layer = scene.pool.allocate(record.id);
        EXPECT_TRUE(layer.has_value());
        EXPECT_TRUE(scene.pool.upload(record));
        scene.draws.push_back(runtime::PatchDraw::ofTile(record.id, *layer, record.info));
    }
    scene.pool.endFrame();
    runtime::assignSkirtDepths(scene.draws, scene.pool);
    return scene;
}

std::vector<Pose> poses(const runtime::TerrainGeometry& g) {
    const glm::dvec2 size = g.demSize();
    const double low = g.minHeight(), high = g.maxHeight();
    const auto make = [&](std::string name, glm::dvec3 position, double yaw, double pitch,
                          int width, int height, double errorPx) {
        Pose pose{std::move(name), {}, errorPx};
        pose.camera.position = position;
        pose.camera.yaw = yaw;
        pose.camera.pitch = pitch;
        pose.camera.viewportWidth = width;
        pose.camera.viewportHeight = height;
        pose.camera.fovY = 1.0;
        return pose;
    };
    const auto at = [&](double fx, double fy, double z) {
        return glm::dvec3(g.worldAtFraction(fx, fy), z);
    };
    const glm::dvec3 centre = at(0.5, 0.5, 0.0);
    std::vector<Pose> out{
        make("looking down", centre + glm::dvec3(0, 0, high + 0.3 * size.x), 0.3, -1.5708, 640, 480,
             2.0),
        make("near", centre + glm::dvec3(0, 0, high + 2.0), 1.0, -0.2, 1280, 720, 2.0),
        make("grazing", at(0.1, 0.1, high + 1.0), 2.4, 0.0, 1920, 1080, 2.0),
        make("far", at(-2.0, -2.0, high + 0.5 * size.x), 2.356, -0.15, 640, 480, 2.0),
        make("below the terrain", centre + glm::dvec3(0, 0, low - 20.0), 0.0, 0.4, 320, 240, 2.0),
        make("oblique, eps 1", at(0.2, 0.8, high + 0.05 * size.x), 0.7, -0.4, 800, 600, 1.0),
        make("oblique, eps 8", at(0.8, 0.2, high + 0.05 * size.x), 3.9, -0.3, 800, 600, 8.0),
    };
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 13; ++i) {
        const double fx = u(random), fy = u(random);
        const glm::dvec3 position =
            at(fx, fy, low + (high - low) * u(random) + 0.4 * size.x * u(random) * u(random));
        out.push_back(make("random " + std::to_string(i), position,
                           2.0 * std::numbers::pi * u(random), -1.5 + 1.6 * u(random),
                           i % 2 == 0 ? 1024 : 320, i % 2 == 0 ? 768 : 240,
                           i % 3 == 0 ? 1.0 : 2.0));
    }
    return out;
}

bool isBorderline(const BlockFactors& cpu, std::size_t edge, double errorPx) {
    for (const double px : cpu.projectedPx[edge]) {
        if (std::abs(px - errorPx) <= kBorderlineRelative * errorPx) return true;
    }
    return false;
}

class TessellationFactorsTest : public GlTest {
protected:
    // A renderer that records every (instance, primitive)'s factors for `scene`'s draws.
    static Result<runtime::TerrainRenderer> recordingRenderer(const Scene& scene) {
        return runtime::TerrainRenderer::create(
            *scene.surface, static_cast<int>(scene.draws.size()), {.recordTessFactors = true});
    }

    // Records a drawn patch leaves: its blocks, then a skirt for each border block of each side.
    static int recordsPerInstance(const io::PyramidLayout& layout) {
        const int blocks = layout.blocksPerSide();
        return blocks * blocks + 4 * blocks;
    }

    static std::vector<RecordedTessFactors> drawAndRecord(runtime::TerrainRenderer& renderer,
                                                          Scene& scene, const Camera& camera,
                                                          const runtime::TerrainStyle& style,
                                                          double errorPx) {
        // Only the control stage's records matter: nothing needs rasterising (the headless
        // context has no default framebuffer, so a small one is bound all the same).
        const gl::Framebuffer target = gl::Framebuffer::create(16, 16).value();
        glBindFramebuffer(GL_FRAMEBUFFER, target.id());
        glEnable(GL_RASTERIZER_DISCARD);
        renderer.draw(camera, scene.pool, scene.draws, style, errorPx);
        glDisable(GL_RASTERIZER_DISCARD);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        return renderer.readTessFactors(static_cast<int>(scene.draws.size()));
    }
};

TEST_F(TessellationFactorsTest, ControlStageMatchesTheCpuModel) {
    Scene scene = loadScene();
    ASSERT_EQ(scene.records.size(), 341u);
    const runtime::TerrainGeometry g(scene.manifest);
    const io::PyramidLayout& layout = g.layout();
    const int blocks = layout.blocksPerSide();
    const int quads = layout.blockQuads();
    const int perInstance = recordsPerInstance(layout);
    auto renderer = recordingRenderer(scene);
    ASSERT_TRUE(renderer) << renderer.error().message;

    std::uint64_t edges = 0, borderline = 0, mismatches = 0, coarsened = 0, fullResolution = 0;
    std::uint64_t blocksSeen = 0, cpuCulled = 0, gpuCulled = 0, keptInMargin = 0;
    std::uint64_t innerSeen = 0, coarserInner = 0;     // drawn blocks; inner below every edge
    std::array<std::uint64_t, 5> perSimplification{};  // CPU d of every edge
    double closestPx = std::numeric_limits<double>::infinity();  // min |proj − ε| / ε
    for (const Pose& pose : poses(g)) {
        SCOPED_TRACE(pose.name);
        runtime::TerrainStyle style;
        style.coarseCells = false;  // every patch as blocks: the edge rule everywhere
        const std::vector<RecordedTessFactors> gpu =
            drawAndRecord(renderer.value(), scene, pose.camera, style, pose.errorPx);
        int failures = 0;  // messages per pose, not per edge
        for (std::size_t i = 0; i < scene.records.size(); ++i) {
            const io::PatchRecord& record = scene.records[i];
            const std::vector<BlockFactors> cpu =
                runtime::patchBlockFactors(pose.camera, g, record, pose.errorPx);
            const RecordedTessFactors* patch = &gpu[i * static_cast<std::size_t>(perInstance)];
            for (int b = 0; b < blocks * blocks; ++b) {
                const RecordedTessFactors& got = patch[b];
                const BlockFactors& want = cpu[static_cast<std::size_t>(b)];
                EXPECT_FALSE(got.isSkirt());
                // Culling: the GPU never discards a block the exact CPU test keeps; it may
                // keep one the CPU discards when the box is within its float margin.
                ++blocksSeen;
                cpuCulled += want.culled ? 1 : 0;
                gpuCulled += got.culled() ? 1 : 0;
                keptInMargin += want.culled && !got.culled() ? 1 : 0;
                EXPECT_TRUE(!got.culled() || want.culled)
                    << "patch L" << record.id.level << " (" << record.id.x << ", " << record.id.y
                    << ") block " << b << " discarded although its box is in view";
                for (std::size_t e = 0; e < 4; ++e) {
                    ++edges;
                    const int factor = got.outer[e];
                    ++perSimplification[static_cast<std::size_t>(want.simplification[e])];
                    for (const double px : want.projectedPx[e]) {
                        closestPx = std::min(closestPx, std::abs(px - pose.errorPx) / pose.errorPx);
                    }
                    EXPECT_TRUE(factor >= 1 && factor <= quads &&
                                std::has_single_bit(static_cast<unsigned>(factor)))
                        << "factor " << factor;
                    if (factor == want.outer[e]) {
                        coarsened += want.simplification[e] > 0 ? 1 : 0;
                        fullResolution += want.simplification[e] == 0 ? 1 : 0;
                        continue;
                    }
                    ++mismatches;
                    if (isBorderline(want, e, pose.errorPx)) {
                        ++borderline;
                        continue;
                    }
                    if (++failures <= 5) {
                        ADD_FAILURE()
                            << "patch L" << record.id.level << " (" << record.id.x << ", "
                            << record.id.y << ") block " << b << " edge " << e << ": GPU factor "
                            << factor << ", CPU " << want.outer[e] << " (projected "
                            << want.projectedPx[e][0] << ", " << want.projectedPx[e][1] << ", "
                            << want.projectedPx[e][2] << ", " << want.projectedPx[e][3] << " px)";
                    }
                }
                // The inner level: never finer than the coarsest edge, and the CPU's where the
                // edges and the block's own projected errors are clear of ε.
                const int minimum = *std::min_element(got.outer.begin(), got.outer.end());
                EXPECT_EQ(got.inner[0], got.inner[1]);
                EXPECT_LE(got.inner[0], minimum);
                EXPECT_TRUE(std::has_single_bit(static_cast<unsigned>(got.inner[0])));
                if (!got.culled()) {
                    ++innerSeen;
                    coarserInner += got.inner[0] < minimum ? 1 : 0;
                }
                const bool edgesAgree =
                    std::equal(got.outer.begin(), got.outer.end(), want.outer.begin());
                if (edgesAgree && got.inner[0] != want.inner[0]) {
                    const bool borderlineInner = std::any_of(
                        want.innerProjectedPx.begin(), want.innerProjectedPx.end(), [&](double px) {
                            return std::abs(px - pose.errorPx) <=
                                   kBorderlineRelative * pose.errorPx;
                        });
                    EXPECT_TRUE(borderlineInner)
                        << "patch L" << record.id.level << " (" << record.id.x << ", "
                        << record.id.y << ") block " << b << ": GPU inner " << got.inner[0]
                        << ", CPU " << want.inner[0];
                }
            }
            // Shared edges inside the patch: bit-identical from both blocks.
            for (int by = 0; by < blocks; ++by) {
                for (int bx = 0; bx < blocks; ++bx) {
                    const RecordedTessFactors& here = patch[by * blocks + bx];
                    if (bx + 1 < blocks) {
                        EXPECT_EQ(here.outer[2], patch[by * blocks + bx + 1].outer[0]);
                    }
                    if (by + 1 < blocks) {
                        EXPECT_EQ(here.outer[3], patch[(by + 1) * blocks + bx].outer[1]);
                    }
                }
            }
            // Skirts: edge e of border block k along that side, (1, f, 1, f) with f the block
            // edge's factor, dropping Λ_ec(d) + the skirt depth.
            for (int e = 0; e < 4; ++e) {
                for (int k = 0; k < blocks; ++k) {
                    const RecordedTessFactors& skirt = patch[blocks * blocks + e * blocks + k];
                    const int bx = e == 0 ? 0 : e == 2 ? blocks - 1 : k;
                    const int by = e == 1 ? 0 : e == 3 ? blocks - 1 : k;
                    const auto ue = static_cast<std::size_t>(e);
                    const RecordedTessFactors& block = patch[by * blocks + bx];
                    const int f = block.outer[ue];
                    EXPECT_TRUE(skirt.isSkirt());
                    EXPECT_EQ(skirt.outer, (std::array<std::int32_t, 4>{1, f, 1, f}));
                    EXPECT_EQ(skirt.inner, (std::array<std::int32_t, 2>{f, 1}));
                    const BlockFactors& want = cpu[static_cast<std::size_t>(by * blocks + bx)];
                    if (f == want.outer[ue]) {
                        const double drop = want.edgeErrorM[ue] + scene.draws[i].skirtDepthM;
                        EXPECT_NEAR(skirt.skirtDropM, drop, 1e-5 * drop + 1e-6);
                    }
                }
            }
        }
    }
    std::cout << "[          ] " << edges << " block edges, " << coarsened << " coarsened, "
              << fullResolution << " at full resolution; " << mismatches << " GPU/CPU mismatches, "
              << borderline << " of them borderline (|proj − ε| ≤ " << kBorderlineRelative
              << " ε); edges per d = 0..4:";
    for (const std::uint64_t n : perSimplification) std::cout << " " << n;
    std::cout << "; closest |proj − ε| / ε " << closestPx << "; blocks " << blocksSeen
              << ", culled by the CPU model " << cpuCulled << ", by the GPU " << gpuCulled
              << " (kept within the margin " << keptInMargin
              << "); inner coarser than every edge in " << coarserInner << " of the " << innerSeen
              << " drawn\n";
    RecordProperty("block_edges", std::to_string(edges));
    RecordProperty("borderline_mismatches", std::to_string(borderline));
    EXPECT_EQ(mismatches, borderline);
    // The poses see part of the pyramid: culling happens, and the margin keeps few.
    EXPECT_GT(cpuCulled, blocksSeen / 10);
    EXPECT_LE(keptInMargin, cpuCulled / 50);
    // The poses exercise the whole range: every edge neither coarsened nor fine.
    EXPECT_GT(coarsened, edges / 10);
    EXPECT_GT(fullResolution, edges / 100);
    // Some drawn blocks take an inner level coarser than every edge (165 of 38,462 here),
    // so the GPU/CPU comparison above covers that rule too.
    EXPECT_GT(coarserInner, 0u);
    RecordProperty("blocks_inner_coarser_than_edges", std::to_string(coarserInner));
}

TEST_F(TessellationFactorsTest, FixedFactorIsUniformAndSkirtsDropItsBlockError) {
    Scene scene = loadScene();
    const runtime::TerrainGeometry g(scene.manifest);
    const io::PyramidLayout& layout = g.layout();
    const int blocks = layout.blocksPerSide();
    const int perInstance = recordsPerInstance(layout);
    auto renderer = recordingRenderer(scene);
    ASSERT_TRUE(renderer) << renderer.error().message;
    const Camera camera = poses(g).front().camera;
    for (const int requested : {1, 2, 3, 8, 100}) {
        SCOPED_TRACE("fixedTessFactor " + std::to_string(requested));
        runtime::TerrainStyle style;
        style.fixedTessFactor = requested;
        const int expected = std::bit_floor(static_cast<unsigned>(std::min(requested, 8)));
        const int d = std::countr_zero(8u) - std::countr_zero(static_cast<unsigned>(expected));
        const std::vector<RecordedTessFactors> gpu =
            drawAndRecord(renderer.value(), scene, camera, style, kFixedFactorErrorPx);
        for (std::size_t i = 0; i < scene.records.size(); ++i) {
            const RecordedTessFactors* patch = &gpu[i * static_cast<std::size_t>(perInstance)];
            for (int b = 0; b < blocks * blocks; ++b) {
                EXPECT_EQ(patch[b].outer,
                          (std::array<std::int32_t, 4>{expected, expected, expected, expected}));
            }
            // The west skirt of block (0, 0): Λ(d) of that block alone, plus the skirt depth.
            const io::PatchRecord& record = scene.records[i];
            const double lambda =
                d == 0
                    ? 0.0
                    : static_cast<double>(record.blockErrors[0][static_cast<std::size_t>(d - 1)]);
            const double drop = lambda + record.info.error + scene.draws[i].skirtDepthM;
            EXPECT_NEAR(patch[blocks * blocks].skirtDropM, drop, 1e-5 * drop + 1e-6);
        }
    }
}

// TerrainStyle::lodCamera: the factors are the LOD camera's wherever the drawn camera is
// (terrain-bench draws the previous frame's LOD from this frame's camera this way).
TEST_F(TessellationFactorsTest, LodCameraDecidesTheFactors) {
    Scene scene = loadScene();
    const runtime::TerrainGeometry g(scene.manifest);
    const io::PyramidLayout& layout = g.layout();
    const int blocks = layout.blocksPerSide();
    const int perInstance = recordsPerInstance(layout);
    auto renderer = recordingRenderer(scene);
    ASSERT_TRUE(renderer) << renderer.error().message;
    const std::vector<Pose> all = poses(g);
    std::uint64_t compared = 0, differFromDrawn = 0;
    for (std::size_t p = 0; p + 1 < all.size(); p += 2) {
        const Pose& lodPose = all[p];
        Camera drawn = all[p + 1].camera;  // another pose, seen through the same viewport
        drawn.viewportWidth = lodPose.camera.viewportWidth;
        drawn.viewportHeight = lodPose.camera.viewportHeight;
        SCOPED_TRACE(lodPose.name + " drawn from " + all[p + 1].name);
        runtime::TerrainStyle style;
        style.cullBlocks = false;  // culling follows the drawn camera; the factors do not
        style.coarseCells = false;
        style.lodCamera = lodPose.camera;
        const std::vector<RecordedTessFactors> gpu =
            drawAndRecord(renderer.value(), scene, drawn, style, lodPose.errorPx);
        for (std::size_t i = 0; i < scene.records.size(); ++i) {
            const std::vector<BlockFactors> want =
                runtime::patchBlockFactors(lodPose.camera, g, scene.records[i], lodPose.errorPx);
            const std::vector<BlockFactors> ofDrawn =
                runtime::patchBlockFactors(drawn, g, scene.records[i], lodPose.errorPx);
            const RecordedTessFactors* patch = &gpu[i * static_cast<std::size_t>(perInstance)];
            for (int b = 0; b < blocks * blocks; ++b) {
                const BlockFactors& cpu = want[static_cast<std::size_t>(b)];
                bool borderline = false;
                for (std::size_t e = 0; e < 4; ++e)
                    borderline |= isBorderline(cpu, e, lodPose.errorPx);
                for (const double px : cpu.innerProjectedPx)
                    borderline |=
                        std::abs(px - lodPose.errorPx) <= kBorderlineRelative * lodPose.errorPx;
                if (borderline) continue;
                ++compared;
                differFromDrawn += cpu.outer != ofDrawn[static_cast<std::size_t>(b)].outer ? 1 : 0;
                EXPECT_EQ(patch[b].outer,
                          (std::array<std::int32_t, 4>{cpu.outer[0], cpu.outer[1], cpu.outer[2],
                                                       cpu.outer[3]}));
                EXPECT_EQ(patch[b].inner[0], cpu.inner[0]);
            }
        }
    }
    // The poses differ enough that the drawn camera alone would give other factors.
    EXPECT_GT(differFromDrawn, compared / 10);
    RecordProperty("blocks_compared", std::to_string(compared));
}

// Coarse cells (CoarseCells.h): where the CPU finds every cell of a patch within ε, the cell's
// north-west block draws it at factor 1 and the blocks it covers are discarded; the skirts
// follow the cells, and every skirt of the frame reaches the cells' Λ.
TEST_F(TessellationFactorsTest, CoarseCellsAreTheCpuChoiceAndCoverTheirBlocks) {
    Scene scene = loadScene();
    const runtime::TerrainGeometry g(scene.manifest);
    const io::PyramidLayout& layout = g.layout();
    const int blocks = layout.blocksPerSide();
    const int perInstance = recordsPerInstance(layout);
    auto renderer = recordingRenderer(scene);
    ASSERT_TRUE(renderer) << renderer.error().message;
    std::uint64_t coarsePatches = 0, blockPatches = 0;
    std::array<std::uint64_t, 5> perCellSize{};  // k = 1..4 by index
    for (const Pose& pose : poses(g)) {
        SCOPED_TRACE(pose.name);
        runtime::TerrainStyle style;
        const std::vector<RecordedTessFactors> gpu =
            drawAndRecord(renderer.value(), scene, pose.camera, style, pose.errorPx);
        // The CPU's choice, from the pool's bounds as the renderer reads them, which are
        // io::coarseCellErrors of the record.
        std::vector<runtime::CoarseCellChoice> choices;
        double depthM = 0.0;
        for (std::size_t i = 0; i < scene.records.size(); ++i) {
            const io::PatchRecord& record = scene.records[i];
            const std::span<const float> bounds = scene.pool.coarseCellErrorsM(record.id);
            const int t = layout.tileSamples();
            const io::GridView interior{record.heights.data() + t + 1, layout.patchSamples(), t};
            const std::vector<float> own =
                io::coarseCellErrors(interior, layout.blockQuads(), record.blockErrors);
            ASSERT_TRUE(std::equal(bounds.begin(), bounds.end(), own.begin(), own.end()));
            choices.push_back(runtime::coarseCellChoice(pose.camera, g, record.id, record.info,
                                                        bounds, pose.errorPx));
            depthM = std::max(
                {depthM, static_cast<double>(scene.draws[i].skirtDepthM), choices.back().errorM});
        }
        for (std::size_t i = 0; i < scene.records.size(); ++i) {
            const runtime::CoarseCellChoice& choice = choices[i];
            const RecordedTessFactors* patch = &gpu[i * static_cast<std::size_t>(perInstance)];
            const int cellBlocks = choice.coarse() ? choice.cellQuads / layout.blockQuads() : 1;
            if (choice.coarse()) {
                ++coarsePatches;
                ++perCellSize[static_cast<std::size_t>(
                    std::countr_zero(static_cast<unsigned>(cellBlocks)))];
            } else {
                ++blockPatches;
            }
            for (int b = 0; b < blocks * blocks; ++b) {
                const RecordedTessFactors& got = patch[b];
                const bool drawsCell =
                    (b % blocks) % cellBlocks == 0 && (b / blocks) % cellBlocks == 0;
                if (!choice.coarse()) {
                    EXPECT_FALSE(got.merged());
                } else if (drawsCell) {
                    EXPECT_FALSE(got.merged());
                    EXPECT_EQ(got.outer, (std::array<std::int32_t, 4>{1, 1, 1, 1}));
                    EXPECT_EQ(got.inner, (std::array<std::int32_t, 2>{1, 1}));
                } else {
                    EXPECT_TRUE(got.merged());
                    EXPECT_EQ(got.outer, (std::array<std::int32_t, 4>{0, 0, 0, 0}));
                }
            }
            for (int e = 0; e < 4; ++e) {
                for (int k = 0; k < blocks; ++k) {
                    const RecordedTessFactors& skirt = patch[blocks * blocks + e * blocks + k];
                    EXPECT_TRUE(skirt.isSkirt());
                    if (!choice.coarse()) {
                        EXPECT_FALSE(skirt.merged());
                        continue;
                    }
                    EXPECT_EQ(skirt.merged(), k % cellBlocks != 0);
                    if (skirt.merged()) continue;
                    EXPECT_EQ(skirt.outer, (std::array<std::int32_t, 4>{1, 1, 1, 1}));
                    const double drop = choice.errorM + depthM;
                    EXPECT_NEAR(skirt.skirtDropM, drop, 1e-5 * drop + 1e-6);
                }
            }
        }
    }
    std::cout << "[          ] patches drawn as coarse cells " << coarsePatches << ", as blocks "
              << blockPatches << "; cells of 2, 4, 8, 16 blocks: " << perCellSize[1] << ", "
              << perCellSize[2] << ", " << perCellSize[3] << ", " << perCellSize[4] << "\n";
    // The poses see both: far patches as cells, near ones as blocks, and more than one size.
    EXPECT_GT(coarsePatches, 0u);
    EXPECT_GT(blockPatches, coarsePatches / 10);
    EXPECT_GE(std::count_if(perCellSize.begin() + 1, perCellSize.end(),
                            [](std::uint64_t n) { return n > 0; }),
              2);
}

TEST_F(TessellationFactorsTest, MeasuredDrawCountsItsTrianglesAndRestoresState) {
    Scene scene = loadScene();
    const runtime::TerrainGeometry g(scene.manifest);
    const io::PyramidLayout& layout = g.layout();
    const auto blocks = static_cast<std::uint64_t>(layout.blocksPerSide());
    const auto quads = static_cast<std::uint64_t>(layout.blockQuads());
    const auto instances = static_cast<std::uint64_t>(scene.draws.size());
    auto renderer = runtime::TerrainRenderer::create(*scene.surface, static_cast<int>(instances));
    ASSERT_TRUE(renderer) << renderer.error().message;
    auto fb = gl::Framebuffer::create(64, 64);
    ASSERT_TRUE(fb) << fb.error().message;
    Camera camera = poses(g).front().camera;
    camera.viewportWidth = camera.viewportHeight = 64;
    glBindFramebuffer(GL_FRAMEBUFFER, fb.value().id());
    glViewport(0, 0, 64, 64);

    runtime::TerrainStyle style;
    style.fixedTessFactor = static_cast<int>(quads);
    style.measure = true;
    style.skirts = false;
    style.wireframe = true;
    style.cullBlocks = false;  // every block counts
    const runtime::TerrainDrawStats plain =
        renderer.value().draw(camera, scene.pool, scene.draws, style, kFixedFactorErrorPx);
    EXPECT_EQ(plain.drawCalls, 1);
    EXPECT_EQ(plain.instances, static_cast<int>(instances));
    // Every block fully tessellated: 2 · B² triangles.
    EXPECT_EQ(plain.triangles, instances * blocks * blocks * 2 * quads * quads);
    EXPECT_GT(plain.gpuMs, 0.0);
    GLint polygonMode[2] = {0, 0};
    glGetIntegerv(GL_POLYGON_MODE, polygonMode);
    EXPECT_EQ(polygonMode[0], GL_FILL);

    style.skirts = true;
    style.wireframe = false;
    const runtime::TerrainDrawStats skirted =
        renderer.value().draw(camera, scene.pool, scene.draws, style, kFixedFactorErrorPx);
    // A skirt: outer (1, B, 1, B), inner (B, 1 → 2): 2(B − 2) + 2B + 2 = 4B − 2 triangles
    // (GL 4.5 §11.2.2.2; the arithmetic TessellationTest checks); one per border block of
    // every patch edge but those on the DEM's own edge (skirtAlongSurfaceEdge: no patch
    // lies beyond them).
    std::uint64_t skirtedEdges = 0;
    for (const runtime::PatchDraw& d : scene.draws) {
        const std::int64_t span = layout.patchQuads() * layout.levelStep(d.id.level);
        const std::int64_t x0 = d.id.x * span, y0 = d.id.y * span;
        skirtedEdges += (x0 > 0 ? 1 : 0) + (y0 > 0 ? 1 : 0) +
                        (x0 + span < layout.rasterWidth() - 1 ? 1 : 0) +
                        (y0 + span < layout.rasterHeight() - 1 ? 1 : 0);
    }
    EXPECT_LT(skirtedEdges, 4 * instances);  // the scene reaches the DEM's edge
    EXPECT_EQ(skirted.triangles - plain.triangles, skirtedEdges * blocks * (4 * quads - 2));

    // Culling blocks outside the 64² view of the same pose draws fewer triangles.
    style.cullBlocks = true;
    const runtime::TerrainDrawStats culled =
        renderer.value().draw(camera, scene.pool, scene.draws, style, kFixedFactorErrorPx);
    EXPECT_LT(culled.triangles, skirted.triangles);

    style.measure = false;
    const runtime::TerrainDrawStats unmeasured =
        renderer.value().draw(camera, scene.pool, scene.draws, style, kFixedFactorErrorPx);
    EXPECT_EQ(unmeasured.triangles, 0u);
    EXPECT_EQ(unmeasured.gpuMs, 0.0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace
}  // namespace terrain::test
