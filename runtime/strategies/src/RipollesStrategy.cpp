// RipollesStrategy: the height field uploaded once, the steps of each frame, and the draw of
// the current tessellation.
#include "terrain/runtime/RipollesStrategy.h"

#include "terrain/gl/Framebuffer.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/FinestLevelRaster.h"
#include "terrain/runtime/IndirectTriangleDraw.h"
#include "terrain/runtime/ProgramBuilder.h"

#include "Bindings.h"

#include <epoxy/gl.h>
#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <chrono>

namespace terrain::runtime {
namespace {

using Clock = std::chrono::steady_clock;

// The counter words of ripolles_tessellation.glsl and ripolles_bookkeeping.comp.
constexpr std::uint32_t kLeavesWord = 0, kFamilyBumpWord = 2, kFreeSlotsWord = 3, kChangesWord = 6,
                        kLeafPointsWord = 12, kFamilyDispatchWord = 16, kFreedDispatchWord = 20,
                        kDrawWord = 24, kTotalWords = 28;
constexpr std::size_t kLeafBytes = 32;                        // Leaf: three vec2, two int
constexpr std::size_t kFamilyBytes = 48;                      // Family: three vec2, six int
constexpr std::size_t kSlotBytes = 2 * sizeof(std::int32_t);  // a free and a freed slot
constexpr std::uint32_t kInputTriangles = 4;
constexpr std::uint64_t kFirstCapacity = 1 << 14;

struct InputLeaf {
    float v[6];
    std::int32_t family;
    std::int32_t childType;
};
static_assert(sizeof(InputLeaf) == kLeafBytes);

std::size_t textureBytesFor(int width, int height) {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * sizeof(float);
}

Result<gl::Program> buildProgram(std::string label, std::initializer_list<std::string> stages,
                                 std::vector<std::string> feedback = {}) {
    ProgramBuilder builder(std::move(label));
    for (const std::string& s : stages) builder.stage(s);
    if (!feedback.empty()) builder.transformFeedback(std::move(feedback));
    return builder.build();
}

GLintptr wordOffset(std::uint32_t word) {
    return static_cast<GLintptr>(word * sizeof(std::uint32_t));
}

void barrier() {
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
}

}  // namespace

Result<std::unique_ptr<RipollesStrategy>> RipollesStrategy::open(
    const std::filesystem::path& pyramid, double thresholdPx, RipollesParameters parameters,
    std::size_t maxBytes) {
    auto reader = openPlanarPyramid(pyramid, "Ripolles's GPU tessellation");
    if (!reader) return reader.error();
    const io::PyramidManifest& manifest = reader.value().manifest();
    const auto width = static_cast<int>(manifest.layout.rasterWidth());
    const auto height = static_cast<int>(manifest.layout.rasterHeight());
    if (const std::size_t need = 2 * textureBytesFor(width, height); need > maxBytes)
        return Error{fmt::format(
            "{}: {} × {} samples need {} MiB for the height field (on the GPU and, while it is "
            "read, in memory), over the {} MiB this method may hold (it keeps the whole finest "
            "level in core, as the paper does)",
            pyramid.string(), width, height, need >> 20, maxBytes >> 20)};
    auto raster = readFinestLevel(reader.value());
    if (!raster) return Error{pyramid.string() + ": " + raster.error().message};
    auto strategy = create(manifest, std::move(raster).value(), thresholdPx, parameters, maxBytes);
    if (!strategy) return Error{pyramid.string() + ": " + strategy.error().message};
    return strategy;
}

Result<std::unique_ptr<RipollesStrategy>> RipollesStrategy::create(
    const io::PyramidManifest& manifest, std::vector<float> heights, double thresholdPx,
    RipollesParameters parameters, std::size_t maxBytes) {
    Programs programs;
    auto families = buildProgram("ripolles families", {"ripolles_families.comp"});
    if (!families) return families.error();
    // The next tessellation's triangles, captured as Leaf records (ripolles_tessellation.glsl).
    auto step = buildProgram("ripolles step", {"ripolles_step.vert", "ripolles_step.geom"},
                             {"o_v0", "o_v1", "o_v2", "o_family", "o_childType"});
    if (!step) return step.error();
    auto bookkeeping = buildProgram("ripolles bookkeeping", {"ripolles_bookkeeping.comp"});
    if (!bookkeeping) return bookkeeping.error();
    auto merge = buildProgram("ripolles merge", {"ripolles_merge.comp"});
    if (!merge) return merge.error();
    auto draw = buildProgram("ripolles draw", {"ripolles_draw.vert", "reference.frag"});
    if (!draw) return draw.error();
    programs.families = std::move(families).value();
    programs.step = std::move(step).value();
    programs.bookkeeping = std::move(bookkeeping).value();
    programs.merge = std::move(merge).value();
    programs.draw = std::move(draw).value();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "ripolles GPU time");
    if (!time) return time.error();
    // The step's draw rasterises nothing, but a draw needs a complete framebuffer.
    auto target = gl::Framebuffer::create(1, 1, "ripolles step target");
    if (!target) return target.error();

    std::unique_ptr<RipollesStrategy> strategy(
        new RipollesStrategy(manifest, std::move(programs), std::move(time).value(),
                             std::move(target).value(), thresholdPx, parameters, maxBytes));
    if (auto uploaded = strategy->upload(heights); !uploaded) return uploaded.error();
    strategy->reset();
    return strategy;
}

RipollesStrategy::RipollesStrategy(const io::PyramidManifest& manifest, Programs programs,
                                   gl::Query timeQuery, gl::Framebuffer stepTarget,
                                   double thresholdPx, RipollesParameters parameters,
                                   std::size_t maxBytes)
    : m_surface(std::make_unique<PlaneSurface>(manifest)),
      m_frame(m_surface->geometry(), "ripolles frame"),
      m_programs(std::move(programs)),
      m_timeQuery(std::move(timeQuery)),
      m_stepTarget(std::move(stepTarget)),
      m_emptyVertexArray(gl::VertexArray::create("ripolles draw (no attributes)")),
      m_thresholdPx(thresholdPx),
      m_parameters(parameters),
      m_maxBytes(maxBytes) {}

RipollesStrategy::~RipollesStrategy() = default;

Status RipollesStrategy::upload(const std::vector<float>& heights) {
    const auto width = static_cast<int>(m_surface->geometry().layout().rasterWidth());
    const auto height = static_cast<int>(m_surface->geometry().layout().rasterHeight());
    if (width < 2 || height < 2) return Error{"the raster needs at least 2 × 2 samples"};
    if (textureBytesFor(width, height) > m_maxBytes)
        return Error{fmt::format("{} × {} samples are over the {} MiB this method may hold", width,
                                 height, m_maxBytes >> 20)};
    // The square of 2^d quads the input mesh covers: the raster, padded.
    m_squareSamples =
        static_cast<int>(std::bit_ceil(static_cast<unsigned>(std::max(width, height) - 1)));
    auto texture = gl::Texture::create2D({GL_R32F, width, height, 1, 1}, "ripolles height field");
    if (!texture) return texture.error();
    m_heights = std::move(texture).value();
    m_heights.upload({0, 0, 0, 0, width, height, 1}, GL_RED, GL_FLOAT,
                     std::as_bytes(std::span(heights)));
    m_heights.setSampling(GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    const std::vector<std::uint32_t> zeros(kTotalWords, 0u);
    m_counters = gl::Buffer::create(kTotalWords * sizeof(std::uint32_t), GL_DYNAMIC_STORAGE_BIT,
                                    "ripolles counters and arguments", zeros.data());
    return {};
}

void RipollesStrategy::reset() {
    if (m_leafCapacity < kFirstCapacity || m_familyCapacity < kFirstCapacity) {
        m_leafCapacity = std::max(m_leafCapacity, kFirstCapacity);
        m_familyCapacity = std::max(m_familyCapacity, kFirstCapacity);
        for (gl::Buffer& leaves : m_leaves)
            leaves = gl::Buffer::create(m_leafCapacity * kLeafBytes, GL_DYNAMIC_STORAGE_BIT,
                                        "ripolles leaves");
        m_families = gl::Buffer::create(m_familyCapacity * kFamilyBytes, 0, "ripolles families");
        m_freeSlots = gl::Buffer::create(m_familyCapacity * kSlotBytes / 2, 0, "ripolles free");
        m_freedSlots = gl::Buffer::create(m_familyCapacity * kSlotBytes / 2, 0, "ripolles freed");
    }
    // Four right triangles about the square's centre, each with its hypotenuse (v0v1) on
    // the square's side.
    const auto n = static_cast<float>(m_squareSamples);
    const std::array<std::array<float, 2>, 4> corners{{{0, 0}, {n, 0}, {n, n}, {0, n}}};
    std::array<InputLeaf, kInputTriangles> input{};
    for (std::uint32_t i = 0; i < kInputTriangles; ++i) {
        const auto& a = corners[i];
        const auto& b = corners[(i + 1) % 4];
        input[i] = {{a[0], a[1], b[0], b[1], n / 2, n / 2}, -1, static_cast<std::int32_t>(i)};
    }
    m_leaves[m_current].upload(0, std::as_bytes(std::span(input)));
    bookkeeping(2);
    m_counts = {};
    m_counts.triangles = kInputTriangles;
    m_familySlots = 0;
}

bool RipollesStrategy::reserve() {
    const std::uint64_t leaves = std::max<std::uint64_t>(4 * m_counts.triangles, kFirstCapacity);
    const std::uint64_t families = m_familySlots + m_counts.triangles;
    if (leaves <= m_leafCapacity && families <= m_familyCapacity) return true;
    const std::uint64_t leafCapacity = std::max(m_leafCapacity, std::bit_ceil(leaves + leaves / 4));
    const std::uint64_t familyCapacity =
        std::max(m_familyCapacity, std::bit_ceil(families + families / 4));
    const std::uint64_t bytes = textureBytesFor(m_heights.width(), m_heights.height()) +
                                2 * leafCapacity * kLeafBytes +
                                familyCapacity * (kFamilyBytes + kSlotBytes);
    if (bytes > m_maxBytes) {
        if (!m_warnedOverBudget)
            fmt::print(stderr,
                       "ripolles: this view's tessellation needs {:.1f} MiB, over the {:.1f} MiB "
                       "the method may hold; it stays as it is\n",
                       static_cast<double>(bytes) / (1 << 20),
                       static_cast<double>(m_maxBytes) / (1 << 20));
        m_warnedOverBudget = true;
        return false;
    }
    // Grown, the current tessellation, the families and the free slots copied over.
    const auto grow = [](gl::Buffer& buffer, std::uint64_t size, std::uint64_t keep,
                         GLbitfield flags, const char* label) {
        gl::Buffer grown = gl::Buffer::create(size, flags, label);
        if (keep > 0)
            glCopyNamedBufferSubData(buffer.id(), grown.id(), 0, 0, static_cast<GLsizeiptr>(keep));
        buffer = std::move(grown);
    };
    if (leafCapacity > m_leafCapacity) {
        grow(m_leaves[m_current], leafCapacity * kLeafBytes, m_counts.triangles * kLeafBytes,
             GL_DYNAMIC_STORAGE_BIT, "ripolles leaves");
        grow(m_leaves[1 - m_current], leafCapacity * kLeafBytes, 0, GL_DYNAMIC_STORAGE_BIT,
             "ripolles leaves");
        m_leafCapacity = leafCapacity;
    }
    if (familyCapacity > m_familyCapacity) {
        grow(m_families, familyCapacity * kFamilyBytes, m_familySlots * kFamilyBytes, 0,
             "ripolles families");
        grow(m_freeSlots, familyCapacity * kSlotBytes / 2, m_familySlots * kSlotBytes / 2, 0,
             "ripolles free");
        grow(m_freedSlots, familyCapacity * kSlotBytes / 2, 0, 0, "ripolles freed");
        m_familyCapacity = familyCapacity;
    }
    return true;
}

void RipollesStrategy::setMethodUniforms(gl::Program& program) const {
    program.setUniform("u_rasterSize",
                       std::array<float, 2>{static_cast<float>(m_heights.width()),
                                            static_cast<float>(m_heights.height())});
    program.setUniform("u_thresholdPx", static_cast<float>(m_thresholdPx));
}

void RipollesStrategy::bookkeeping(int phase) {
    gl::Program& program = m_programs.bookkeeping;
    program.setUniform("u_phase", phase);
    program.setUniform("u_inputTriangles", kInputTriangles);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_COUNTERS, m_counters.id());
    glUseProgram(program.id());
    glDispatchCompute(1, 1, 1);
    glUseProgram(0);
    barrier();
}

void RipollesStrategy::readCounters() {
    std::array<std::uint32_t, 8> words{};
    m_counters.readBack(0, std::as_writable_bytes(std::span(words)));
    m_counts.triangles = words[kLeavesWord];
    m_familySlots = words[kFamilyBumpWord];
    m_counts.families =
        words[kFamilyBumpWord] - std::min(words[kFreeSlotsWord], words[kFamilyBumpWord]);
    m_counts.changes = words[kChangesWord];
}

bool RipollesStrategy::step(const Camera& camera) {
    if (!reserve()) {
        m_counts.changes = 0;
        return false;
    }
    m_frame.bind(camera, TerrainStyle{}, m_thresholdPx);
    for (gl::Program* p : {&m_programs.families, &m_programs.step}) setMethodUniforms(*p);
    glBindTextureUnit(TERRAIN_BINDING_RIPOLLES_HEIGHTS, m_heights.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_COUNTERS, m_counters.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_LEAVES,
                     m_leaves[m_current].id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_FAMILIES, m_families.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_FREE_SLOTS,
                     m_freeSlots.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_FREED_SLOTS,
                     m_freedSlots.id());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, m_counters.id());
    barrier();

    bookkeeping(0);
    const auto dispatch = [](const gl::Program& program, std::uint32_t argumentsWord) {
        glUseProgram(program.id());
        glDispatchComputeIndirect(wordOffset(argumentsWord));
        barrier();
    };
    dispatch(m_programs.families, kFamilyDispatchWord);
    {
        // The leaves' pass: one point a leaf through the geometry stage, its triangles of the
        // next tessellation captured by transform feedback (§3.2).
        GLint previousTarget = 0;
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previousTarget);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_stepTarget.id());
        glEnable(GL_RASTERIZER_DISCARD);
        glUseProgram(m_programs.step.id());
        glBindVertexArray(m_emptyVertexArray.id());
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, m_counters.id());
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, m_leaves[1 - m_current].id());
        glBeginTransformFeedback(GL_POINTS);
        glDrawArraysIndirect(GL_POINTS, reinterpret_cast<const void*>(wordOffset(kLeafPointsWord)));
        glEndTransformFeedback();
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
        glBindVertexArray(0);
        glDisable(GL_RASTERIZER_DISCARD);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(previousTarget));
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
    }
    bookkeeping(1);
    dispatch(m_programs.merge, kFreedDispatchWord);

    glUseProgram(0);
    PlaneFrame::unbind();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    for (GLuint binding : {TERRAIN_BINDING_RIPOLLES_COUNTERS, TERRAIN_BINDING_RIPOLLES_LEAVES,
                           TERRAIN_BINDING_RIPOLLES_FAMILIES, TERRAIN_BINDING_RIPOLLES_FREE_SLOTS,
                           TERRAIN_BINDING_RIPOLLES_FREED_SLOTS})
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, 0);
    m_current = 1 - m_current;
    readCounters();
    ++m_counts.steps;
    return m_counts.changes > 0;
}

const LodUpdateStats& RipollesStrategy::beginFrame(const Camera& camera) {
    const auto start = Clock::now();
    m_counts.steps = 0;
    if (m_parameters.coherence) {
        step(camera);
    } else {
        // Table 3's other column: from the input mesh, step by step, to what the view asks.
        reset();
        const int maxSteps = 8 * std::bit_width(static_cast<unsigned>(m_squareSamples)) + 8;
        while (m_counts.steps < maxSteps && step(camera)) {
        }
    }
    m_lodUpdateUs = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    m_stats = {};
    m_stats.drawn = m_counts.triangles;
    m_stats.evaluations = m_counts.triangles;
    m_stats.nodes = m_counts.families;
    // Triangles still changing: the view's tessellation is not reached yet (settle() steps on).
    m_stats.waitingSplits = m_counts.changes;
    m_lastDraw = {};
    return m_stats;
}

bool RipollesStrategy::settle(const Camera& camera, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    const int maxSteps = 16 * std::bit_width(static_cast<unsigned>(m_squareSamples)) + 16;
    for (int i = 0; i < maxSteps && Clock::now() < deadline; ++i) {
        if (!step(camera)) return true;
    }
    return false;
}

TerrainDrawStats RipollesStrategy::draw(const Camera& camera, const TerrainStyle& style) {
    gl::Program& program = m_programs.draw;
    m_frame.bind(camera, style, m_thresholdPx);
    setMethodUniforms(program);
    TerrainDrawStats stats;
    stats.drawCalls = 1;
    stats.instances = 1;
    stats.triangles = m_counts.triangles;
    glBindTextureUnit(TERRAIN_BINDING_RIPOLLES_HEIGHTS, m_heights.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_LEAVES,
                     m_leaves[m_current].id());
    stats.gpuMs = drawTrianglesIndirect(program, m_emptyVertexArray, m_counters,
                                        kDrawWord * sizeof(std::uint32_t), m_timeQuery, style);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_RIPOLLES_LEAVES, 0);
    PlaneFrame::unbind();
    m_lastDraw = stats;
    return stats;
}

void RipollesStrategy::endFrame(FrameTelemetry& t) {
    writeDrawTelemetry(t, m_lodUpdateUs, m_lastDraw);
}

std::uint64_t RipollesStrategy::memoryBytes() const {
    return textureBytesFor(m_heights.width(), m_heights.height()) + m_counters.sizeBytes() +
           m_leaves[0].sizeBytes() + m_leaves[1].sizeBytes() + m_families.sizeBytes() +
           m_freeSlots.sizeBytes() + m_freedSlots.sizeBytes();
}

std::vector<std::array<glm::vec2, 3>> RipollesStrategy::readTriangles() const {
    std::vector<InputLeaf> leaves(m_counts.triangles);
    if (!leaves.empty()) {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        m_leaves[m_current].readBack(0, std::as_writable_bytes(std::span(leaves)));
    }
    std::vector<std::array<glm::vec2, 3>> triangles(leaves.size());
    for (std::size_t t = 0; t < leaves.size(); ++t)
        for (std::size_t v = 0; v < 3; ++v)
            triangles[t][v] = {leaves[t].v[2 * v], leaves[t].v[2 * v + 1]};
    return triangles;
}

}  // namespace terrain::runtime
