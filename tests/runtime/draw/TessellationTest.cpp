// Draws one quad patch through vertex -> tess control -> tess eval -> fragment and checks
// GL_PRIMITIVES_GENERATED against the GL 4.5 spec's quad tessellation arithmetic, and the
// pixels against the domain coordinates the evaluation stage passes on.
#include "Bindings.h"
#include "GlTestFixture.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

namespace terrain::test {
namespace {

struct TessLevels {
    std::string name;
    std::array<float, 4> outer;  ///< u = 0, v = 0, u = 1, v = 1 edges
    std::array<float, 2> inner;
};

/// Readable test names in gtest output instead of a byte dump.
void PrintTo(const TessLevels& levels, std::ostream* out) {
    *out << "outer (" << levels.outer[0] << ", " << levels.outer[1] << ", " << levels.outer[2]
         << ", " << levels.outer[3] << ") inner (" << levels.inner[0] << ", " << levels.inner[1]
         << ")";
}

/// Segments of one level under equal_spacing: clamped to [1, maxLevel], rounded up.
/// GL 4.5 core §11.2.2 "Tessellation Primitive Generation".
int equalSpacingSegments(float level, int maxLevel) {
    const float clamped = std::clamp(level, 1.0f, static_cast<float>(maxLevel));
    return static_cast<int>(std::ceil(clamped));
}

struct QuadTessellation {
    std::uint64_t triangles = 0;
    std::uint64_t vertices = 0;  ///< distinct domain points
};

/// CPU reference of quad tessellation with equal_spacing, GL 4.5 core §11.2.2.2:
/// - any outer level <= 0 (or NaN) discards the patch (§11.2.2);
/// - all six levels clamped to exactly 1: one triangle pair covering the rectangle;
/// - otherwise an inner level of 1 counts as 1 + epsilon, i.e. 2 segments under
///   equal_spacing;
/// - the inner m x n grid gives 2(m-2)(n-2) triangles for the rectangles away from the
///   border, and the ring between the inner rectangle (2(m-2) + 2(n-2) segments) and the
///   four outer edges (O0 + O1 + O2 + O3 segments) is one triangle per segment on either
///   side: triangles = 2(m-2)(n-2) + 2(m-2) + 2(n-2) + O0 + O1 + O2 + O3.
QuadTessellation referenceQuadTessellation(const TessLevels& levels, int maxLevel) {
    for (float outer : levels.outer) {
        if (!(outer > 0.0f)) {
            return {};
        }
    }
    const auto clampedToOne = [&](float level) {
        return std::clamp(level, 1.0f, static_cast<float>(maxLevel)) == 1.0f;
    };
    if (std::all_of(levels.outer.begin(), levels.outer.end(), clampedToOne) &&
        std::all_of(levels.inner.begin(), levels.inner.end(), clampedToOne)) {
        return {.triangles = 2, .vertices = 4};
    }
    const std::uint64_t m =
        static_cast<std::uint64_t>(std::max(2, equalSpacingSegments(levels.inner[0], maxLevel)));
    const std::uint64_t n =
        static_cast<std::uint64_t>(std::max(2, equalSpacingSegments(levels.inner[1], maxLevel)));
    std::uint64_t outerSegments = 0;
    for (float outer : levels.outer) {
        outerSegments += static_cast<std::uint64_t>(equalSpacingSegments(outer, maxLevel));
    }
    return {.triangles = 2 * (m - 2) * (n - 2) + 2 * (m - 2) + 2 * (n - 2) + outerSegments,
            .vertices = (m - 1) * (n - 1) + outerSegments};
}

TEST(QuadTessellationReference, MatchesHandCountedCases) {
    // All ones: a single triangle pair.
    EXPECT_EQ(referenceQuadTessellation({"", {1, 1, 1, 1}, {1, 1}}, 64).triangles, 2u);
    // All twos: inner 2x2 grid collapses to the centre point, 8 fan triangles.
    EXPECT_EQ(referenceQuadTessellation({"", {2, 2, 2, 2}, {2, 2}}, 64).triangles, 8u);
    // Inner 1 with an outer > 1 becomes 2 segments: same as inner 2.
    EXPECT_EQ(referenceQuadTessellation({"", {2, 1, 1, 1}, {1, 1}}, 64).triangles, 5u);
    // Inner 3x3: one inner quad (2) + ring 2 + 2 + 4 * 3 outer.
    EXPECT_EQ(referenceQuadTessellation({"", {3, 3, 3, 3}, {3, 3}}, 64).triangles, 18u);
    // Uniform level L: 2 L^2 triangles.
    EXPECT_EQ(referenceQuadTessellation({"", {8, 8, 8, 8}, {8, 8}}, 64).triangles, 128u);
    // Levels above the maximum clamp to it; outer 0 discards.
    EXPECT_EQ(referenceQuadTessellation({"", {99, 99, 99, 99}, {99, 99}}, 64).triangles,
              2u * 64u * 64u);
    EXPECT_EQ(referenceQuadTessellation({"", {0, 4, 4, 4}, {4, 4}}, 64).triangles, 0u);
}

// The framebuffer and the quad in pixels; edges on whole pixels, so every pixel centre is
// clearly inside or outside.
constexpr int kWidth = 96;
constexpr int kHeight = 64;
constexpr int kLeft = 16;
constexpr int kRight = 80;
constexpr int kBottom = 8;
constexpr int kTop = 56;
constexpr std::array<float, 4> kClearColor = {0.0f, 0.0f, 1.0f, 1.0f};
constexpr int kColorTolerance = 2;  // of 255: RGBA8 rounding plus interpolation

float toNdc(int pixel, int size) {
    return 2.0f * static_cast<float>(pixel) / static_cast<float>(size) - 1.0f;
}

class TessellationTest : public GlTestWithParam<TessLevels> {
protected:
    void SetUp() override {
        GlTestWithParam<TessLevels>::SetUp();
        if (HasFatalFailure()) {
            return;
        }
        auto program = runtime::ProgramBuilder("tess_test")
                           .stage("tess_test.vert")
                           .stage("tess_test.tesc")
                           .stage("tess_test.tese")
                           .stage("tess_test.frag")
                           .build();
        ASSERT_TRUE(program) << program.error().message;
        m_program = std::move(program).value();
        ASSERT_TRUE(m_program.hasUniform("u_outerLevels"));
        ASSERT_TRUE(m_program.hasUniform("u_innerLevels"));

        auto framebuffer = gl::Framebuffer::create(kWidth, kHeight, "tess_test target");
        ASSERT_TRUE(framebuffer) << framebuffer.error().message;
        m_framebuffer = std::move(framebuffer).value();

        // Patch corners in (u, v) order (0,0), (1,0), (1,1), (0,1): see tess_test.tese.
        const std::array<float, 8> corners = {toNdc(kLeft, kWidth),  toNdc(kBottom, kHeight),
                                              toNdc(kRight, kWidth), toNdc(kBottom, kHeight),
                                              toNdc(kRight, kWidth), toNdc(kTop, kHeight),
                                              toNdc(kLeft, kWidth),  toNdc(kTop, kHeight)};
        m_corners = gl::Buffer::createFrom(std::span<const float>(corners), 0, "tess_test corners");
        m_vertexArray = gl::VertexArray::create("tess_test vertices");
        m_vertexArray.setVertexBuffer(0, m_corners, 0, 2 * sizeof(float));
        m_vertexArray.setFloatAttribute(TERRAIN_ATTRIB_POSITION, 0, 2, GL_FLOAT, false, 0);
    }

    /// Draws the patch with `levels`; returns primitives generated and, when supported,
    /// tessellation evaluation invocations.
    struct DrawCounts {
        std::uint64_t primitives = 0;
        std::optional<std::uint64_t> evaluations;
        std::uint64_t gpuTimeNs = 0;
    };
    DrawCounts draw(const TessLevels& levels) {
        m_program.setUniform("u_outerLevels", levels.outer);
        m_program.setUniform("u_innerLevels", levels.inner);
        m_framebuffer.clear(kClearColor);

        auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, "primitives");
        auto gpuTime = gl::Query::create(gl::QueryKind::TimeElapsed, "draw time");
        std::optional<gl::Query> evaluations;
        if (gl::Query::isSupported(gl::QueryKind::TessEvaluationInvocations)) {
            evaluations = std::move(
                gl::Query::create(gl::QueryKind::TessEvaluationInvocations, "evaluations").value());
        }

        // All state this draw depends on is set here and put back to defaults after.
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_framebuffer.id());
        glViewport(0, 0, kWidth, kHeight);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE);
        glDisable(GL_BLEND);
        glDisable(GL_SCISSOR_TEST);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        glUseProgram(m_program.id());
        glBindVertexArray(m_vertexArray.id());
        glPatchParameteri(GL_PATCH_VERTICES, 4);

        gpuTime.value().begin();
        primitives.value().begin();
        if (evaluations) {
            evaluations->begin();
        }
        glDrawArrays(GL_PATCHES, 0, 4);
        if (evaluations) {
            evaluations->end();
        }
        primitives.value().end();
        gpuTime.value().end();

        glBindVertexArray(0);
        glUseProgram(0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);

        DrawCounts counts;
        counts.primitives = primitives.value().waitResult();
        counts.gpuTimeNs = gpuTime.value().waitResult();
        if (evaluations) {
            counts.evaluations = evaluations->waitResult();
        }
        return counts;
    }

    gl::Program m_program;
    gl::Framebuffer m_framebuffer;
    gl::Buffer m_corners;
    gl::VertexArray m_vertexArray;
};

TEST_P(TessellationTest, PrimitiveCountMatchesSpecArithmetic) {
    const TessLevels& levels = GetParam();
    GLint maxLevel = 0;
    glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &maxLevel);
    ASSERT_GE(maxLevel, 64);  // the GL 4.5 minimum
    const QuadTessellation expected = referenceQuadTessellation(levels, maxLevel);

    const DrawCounts counts = draw(levels);
    EXPECT_EQ(counts.primitives, expected.triangles);
    EXPECT_LT(counts.gpuTimeNs, 10'000'000'000u);  // sane, not a benchmark
    RecordProperty("gpu_time_ns", std::to_string(counts.gpuTimeNs));
    if (counts.evaluations) {
        // Every distinct domain point is evaluated at least once; implementations may
        // evaluate shared points more than once, so only the lower bound is portable.
        EXPECT_GE(*counts.evaluations, expected.vertices);
        if (expected.triangles == 0) {
            EXPECT_EQ(*counts.evaluations, 0u);
        }
    }
}

TEST_P(TessellationTest, PixelsShowTessCoordInsideAndClearColourOutside) {
    const TessLevels& levels = GetParam();
    GLint maxLevel = 0;
    glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &maxLevel);
    const bool discarded = referenceQuadTessellation(levels, maxLevel).triangles == 0;
    draw(levels);
    const std::vector<std::uint8_t> pixels = m_framebuffer.readColorRgba8();
    ASSERT_EQ(pixels.size(), static_cast<std::size_t>(kWidth * kHeight * 4));

    int mismatches = 0;
    for (int y = 0; y < kHeight && mismatches < 10; ++y) {
        for (int x = 0; x < kWidth && mismatches < 10; ++x) {
            const std::uint8_t* pixel = &pixels[static_cast<std::size_t>((y * kWidth + x) * 4)];
            const bool inside = !discarded && x >= kLeft && x < kRight && y >= kBottom && y < kTop;
            std::array<int, 4> expected{};
            if (inside) {
                // Red = u, green = v: the evaluation stage's gl_TessCoord at this centre.
                const float u = (static_cast<float>(x - kLeft) + 0.5f) / (kRight - kLeft);
                const float v = (static_cast<float>(y - kBottom) + 0.5f) / (kTop - kBottom);
                expected = {static_cast<int>(std::lround(u * 255.0f)),
                            static_cast<int>(std::lround(v * 255.0f)), 0, 255};
            } else {
                expected = {0, 0, 255, 255};
            }
            for (int channel = 0; channel < 4; ++channel) {
                if (std::abs(pixel[channel] - expected[static_cast<std::size_t>(channel)]) >
                    kColorTolerance) {
                    ADD_FAILURE() << "pixel (" << x << ", " << y << ") "
                                  << (inside ? "inside" : "outside") << " channel " << channel
                                  << ": got " << int(pixel[channel]) << ", expected "
                                  << expected[static_cast<std::size_t>(channel)];
                    ++mismatches;
                    break;
                }
            }
        }
    }
}

std::vector<TessLevels> allTessLevels() {
    std::vector<TessLevels> levels;
    for (int level = 1; level <= 64; ++level) {
        const auto value = static_cast<float>(level);
        levels.push_back(
            {"Equal" + std::to_string(level), {value, value, value, value}, {value, value}});
    }
    levels.push_back({"Outer1234Inner25", {1, 2, 3, 4}, {2, 5}});
    levels.push_back({"Outer1234Inner73", {1, 2, 3, 4}, {7, 3}});
    levels.push_back({"Outer4321Inner11", {4, 3, 2, 1}, {1, 1}});
    levels.push_back({"Outer5111Inner11", {5, 1, 1, 1}, {1, 1}});
    levels.push_back({"Outer1111Inner13", {1, 1, 1, 1}, {1, 3}});
    levels.push_back({"Outer1111Inner31", {1, 1, 1, 1}, {3, 1}});
    levels.push_back({"Outer8_16_32_64Inner64_1", {8, 16, 32, 64}, {64, 1}});
    levels.push_back({"Outer64_1_64_1Inner2_64", {64, 1, 64, 1}, {2, 64}});
    levels.push_back({"FractionalRoundsUp", {2.5f, 1.2f, 3.9f, 1.0f}, {2.1f, 3.5f}});
    levels.push_back({"AlmostAllOnes", {1, 1, 1, 1.2f}, {1, 1}});
    levels.push_back({"BelowOneClampsToAllOnes", {0.5f, 1, 1, 1}, {0.5f, 0.25f}});
    levels.push_back({"AboveMaxClamps", {100, 100, 100, 100}, {100, 80}});
    levels.push_back({"OuterZeroDiscards", {0, 4, 4, 4}, {4, 4}});
    return levels;
}

INSTANTIATE_TEST_SUITE_P(QuadLevels, TessellationTest, ::testing::ValuesIn(allTessLevels()),
                         [](const ::testing::TestParamInfo<TessLevels>& levels) {
                             return levels.param.name;
                         });

}  // namespace
}  // namespace terrain::test
