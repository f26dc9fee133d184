// The strips GL's tessellator puts between a block's edges and its inner mesh, read back
// from the tessellator itself: for every combination of factors the fine LOD can give a
// block of 16 or 8 quads (inner factor at most the smallest edge factor, all powers of
// two), every triangle is
// one that io::transitionErrors models, and none deviates from rough surfaces by more than
// the block's λ(d) for its inner factor. This is the property the fine LOD's bound rests
// on: a block's error is charged to its coarsest edge (EdgeTessellation.h).
#include "GlTestFixture.h"
#include "TriangulationOracle.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/runtime/ProgramBuilder.h"

#include "Bindings.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace terrain::test {
namespace {

constexpr std::size_t kCapacityTriangles = 4096;

struct SamplePoint {
    int x, y;
};
using Triangle = std::array<SamplePoint, 3>;

struct Factors {
    std::array<int, 4> outer;  // GL order: u = 0, v = 0, u = 1, v = 1
    int inner;
};

std::string describe(const Factors& f) {
    return "outer (" + std::to_string(f.outer[0]) + ", " + std::to_string(f.outer[1]) + ", " +
           std::to_string(f.outer[2]) + ", " + std::to_string(f.outer[3]) + ") inner " +
           std::to_string(f.inner);
}

// Rough heights: slopes, a ridge and noise of `noiseM`, on (blockQuads + 1)² samples.
std::vector<float> roughGrid(int blockQuads, unsigned seed, float noiseM) {
    const int n = blockQuads + 1;
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, noiseM);
    std::vector<float> h(static_cast<std::size_t>(n * n));
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            h[static_cast<std::size_t>(y * n + x)] =
                40.0f * std::sin(0.4f * float(x + seed)) +
                25.0f * std::abs(float(y) - 0.47f * float(blockQuads)) + noise(rng);
    return h;
}

class TransitionStripTest : public GlTest, public ::testing::WithParamInterface<int> {
protected:
    void SetUp() override {
        GlTest::SetUp();
        if (HasFatalFailure()) return;
        auto program = runtime::ProgramBuilder("tess_capture")
                           .stage("tess_test.vert")
                           .stage("tess_test.tesc")
                           .stage("tess_test.tese")
                           .stage("tess_capture.geom")
                           .build();
        ASSERT_TRUE(program) << program.error().message;
        m_program = std::move(program).value();
        const std::array<float, 8> corners = {0, 0, 1, 0, 1, 1, 0, 1};
        m_corners = gl::Buffer::createFrom(std::span<const float>(corners), 0, "capture corners");
        m_vertexArray = gl::VertexArray::create("capture vertices");
        m_vertexArray.setVertexBuffer(0, m_corners, 0, 2 * sizeof(float));
        m_vertexArray.setFloatAttribute(TERRAIN_ATTRIB_POSITION, 0, 2, GL_FLOAT, false, 0);
        // A draw needs a complete framebuffer, though nothing is rasterised.
        auto framebuffer = gl::Framebuffer::create(1, 1, "capture target");
        ASSERT_TRUE(framebuffer) << framebuffer.error().message;
        m_framebuffer = std::move(framebuffer).value();
        m_captured = gl::Buffer::create(
            2 * sizeof(std::uint32_t) + kCapacityTriangles * 3 * 2 * sizeof(float),
            GL_DYNAMIC_STORAGE_BIT, "captured triangles");
    }

    // The tessellator's triangles for `factors`, in block samples (domain · blockQuads).
    std::vector<Triangle> capture(const Factors& factors, int blockQuads) {
        const std::array<std::uint32_t, 2> zero{};
        m_captured.upload(0, std::as_bytes(std::span(zero)));
        m_program.setUniform(
            "u_outerLevels",
            std::array<float, 4>{float(factors.outer[0]), float(factors.outer[1]),
                                 float(factors.outer[2]), float(factors.outer[3])});
        m_program.setUniform("u_innerLevels",
                             std::array<float, 2>{float(factors.inner), float(factors.inner)});
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_framebuffer.id());
        glEnable(GL_RASTERIZER_DISCARD);
        glUseProgram(m_program.id());
        glBindVertexArray(m_vertexArray.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_captured.id());
        glPatchParameteri(GL_PATCH_VERTICES, 4);
        glDrawArrays(GL_PATCHES, 0, 4);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        glBindVertexArray(0);
        glUseProgram(0);
        glDisable(GL_RASTERIZER_DISCARD);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);

        std::uint32_t count = 0;
        m_captured.readBack(0, std::as_writable_bytes(std::span(&count, 1)));
        EXPECT_LE(count, kCapacityTriangles);
        count = std::min<std::uint32_t>(count, kCapacityTriangles);
        std::vector<float> domain(static_cast<std::size_t>(count) * 6);
        m_captured.readBack(2 * sizeof(std::uint32_t), std::as_writable_bytes(std::span(domain)));
        std::vector<Triangle> triangles(count);
        for (std::size_t t = 0; t < count; ++t) {
            for (std::size_t i = 0; i < 3; ++i) {
                const float u = domain[6 * t + 2 * i], v = domain[6 * t + 2 * i + 1];
                const float x = u * float(blockQuads), y = v * float(blockQuads);
                // Power-of-two factors put every domain point on a sample.
                EXPECT_NEAR(x, std::round(x), 1e-4) << describe(factors);
                EXPECT_NEAR(y, std::round(y), 1e-4) << describe(factors);
                triangles[t][i] = {int(std::lround(x)), int(std::lround(y))};
            }
        }
        return triangles;
    }

    gl::Program m_program;
    gl::Framebuffer m_framebuffer;
    gl::Buffer m_corners, m_captured;
    gl::VertexArray m_vertexArray;
};

// Every factor combination of a block whose inner factor is that of simplification d.
std::vector<Factors> factorsOfInnerLevel(int blockQuads, int d) {
    const int inner = std::max(1, blockQuads >> d);
    std::vector<int> edge;
    for (int m = inner; m <= blockQuads; m *= 2) edge.push_back(m);
    std::vector<Factors> all;
    for (int a : edge)
        for (int b : edge)
            for (int c : edge)
                for (int e : edge) all.push_back({{a, b, c, e}, inner});
    return all;
}

// Whether `t` is a triangle of the inner mesh (half a cell of `spacing`) or of the strip
// along some edge as io::transitionErrors enumerates it: two consecutive vertices of one
// side and a vertex of the other within one inner spacing of them. `outer` holds the edges' factors
// in the frame order below (v = 0, v = 1, u = 0, u = 1).
bool isModelled(const Triangle& t, int blockQuads, int innerSpacing,
                const std::array<int, 4>& outer) {
    const int n = blockQuads;
    auto minMax = [&](auto get) {
        auto [lo, hi] = std::minmax({get(t[0]), get(t[1]), get(t[2])});
        return std::pair{lo, hi};
    };
    const auto [xLo, xHi] = minMax([](SamplePoint p) { return p.x; });
    const auto [yLo, yHi] = minMax([](SamplePoint p) { return p.y; });
    if (outer == std::array<int, 4>{1, 1, 1, 1})  // no strips: the block is one cell
        return xHi - xLo == n && yHi - yLo == n;
    if (xLo >= innerSpacing && xHi <= n - innerSpacing && yLo >= innerSpacing &&
        yHi <= n - innerSpacing)
        return xHi - xLo == innerSpacing && yHi - yLo == innerSpacing &&
               (xLo % innerSpacing) == 0 && (yLo % innerSpacing) == 0;
    for (int edge = 0; edge < 4; ++edge) {
        // (along, inward) of a sample in edge `edge`'s frame.
        auto frame = [&](SamplePoint p) -> std::array<int, 2> {
            switch (edge) {
                case 0:
                    return {p.x, p.y};
                case 1:
                    return {p.x, n - p.y};
                case 2:
                    return {p.y, p.x};
                default:
                    return {p.y, n - p.x};
            }
        };
        const int outerSpacing = n / outer[static_cast<std::size_t>(edge)];
        std::vector<int> onEdge, onInner;
        bool fits = true;
        for (const SamplePoint& p : t) {
            const auto [along, inward] = frame(p);
            if (inward == 0 && along % outerSpacing == 0)
                onEdge.push_back(along);
            else if (inward == innerSpacing && along >= innerSpacing && along <= n - innerSpacing &&
                     along % innerSpacing == 0)
                onInner.push_back(along);
            else
                fits = false;
        }
        if (!fits) continue;
        // Two consecutive vertices of one side, and a vertex of the other side at most one
        // inner spacing beyond their span.
        auto joins = [&](const std::vector<int>& pair, int spacing, const std::vector<int>& apex) {
            if (pair.size() != 2 || apex.size() != 1 || std::abs(pair[0] - pair[1]) != spacing)
                return false;
            const auto [lo, hi] = std::minmax(pair[0], pair[1]);
            return apex[0] >= lo - innerSpacing && apex[0] <= hi + innerSpacing;
        };
        if (joins(onEdge, outerSpacing, onInner) || joins(onInner, innerSpacing, onEdge))
            return true;
    }
    return false;
}

TEST_P(TransitionStripTest, EveryTriangleIsModelledAndWithinTheBlockError) {
    const int blockQuads = GetParam();
    std::vector<std::vector<float>> grids;
    for (unsigned seed = 1; seed <= 4; ++seed)
        grids.push_back(roughGrid(blockQuads, seed, 6.0f * static_cast<float>(seed)));
    const int side = blockQuads + 1;
    int combinations = 0, triangles = 0;
    double closest = 0.0;  // largest deviation / λ
    for (int d = 1; d <= io::kMaxSimplification; ++d) {
        const int inner = std::max(1, blockQuads >> d);
        const int innerSpacing = blockQuads / std::max(2, inner);
        for (const Factors& factors : factorsOfInnerLevel(blockQuads, d)) {
            ++combinations;
            const std::vector<Triangle> drawn = capture(factors, blockQuads);
            // GL's outer order (u = 0, v = 0, u = 1, v = 1) in the frame order of isModelled.
            const std::array<int, 4> outer = {factors.outer[1], factors.outer[3], factors.outer[0],
                                              factors.outer[2]};
            for (const Triangle& t : drawn) {
                ++triangles;
                ASSERT_TRUE(isModelled(t, blockQuads, innerSpacing, outer))
                    << describe(factors) << ": triangle (" << t[0].x << "," << t[0].y << ") ("
                    << t[1].x << "," << t[1].y << ") (" << t[2].x << "," << t[2].y << ")";
            }
            for (const auto& h : grids) {
                auto height = [&](int x, int y) {
                    return double(h[static_cast<std::size_t>(y * side + x)]);
                };
                const io::BlockErrors lambda =
                    io::blockErrors(io::GridView{h.data(), side, side}, 0, 0, blockQuads);
                const double bound = double(lambda[static_cast<std::size_t>(d - 1)]);
                for (const Triangle& t : drawn) {
                    auto corner = [&](SamplePoint p) {
                        return Point3{double(p.x), double(p.y), height(p.x, p.y)};
                    };
                    const double deviation =
                        triangleSurfaceDeviation(height, corner(t[0]), corner(t[1]), corner(t[2]));
                    ASSERT_LE(deviation, bound * (1.0 + 1e-6) + 1e-6)
                        << describe(factors) << ", λ(" << d << ") = " << bound;
                    closest = std::max(closest, deviation / bound);
                }
            }
        }
    }
    RecordProperty("combinations", combinations);
    RecordProperty("triangles", triangles);
    RecordProperty("largest_deviation_over_lambda", std::to_string(closest));
    EXPECT_GT(closest, 0.5);  // the bound is not vacuous
}

// Yusov's block of 16 quads, and the default of 8 (PyramidLayout::kDefaultBlockQuads).
INSTANTIATE_TEST_SUITE_P(BlockSizes, TransitionStripTest, ::testing::Values(16, 8),
                         [](const ::testing::TestParamInfo<int>& param) {
                             return std::to_string(param.param) + "Quads";
                         });

}  // namespace
}  // namespace terrain::test
