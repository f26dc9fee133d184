// GeometrySplittingStrategy: the textures uploaded once, the passes of each frame, and the
// draw of what they wrote.
#include "terrain/runtime/GeometrySplittingStrategy.h"

#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/FinestLevelRaster.h"
#include "terrain/runtime/IndirectTriangleDraw.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/RoughnessQuadtree.h"

#include "Bindings.h"

#include <epoxy/gl.h>
#include <fmt/core.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

namespace terrain::runtime {
namespace {

using Clock = std::chrono::steady_clock;

// LeeCounters (lee_quadtree.glsl) as words, then the indirect arguments: one dispatch slot
// (4 words) per pass, then the draw's.
constexpr std::uint32_t kMaxPasses = 32;
constexpr std::uint32_t kNodesWord = 0;
constexpr std::uint32_t kPendingWord = kMaxPasses;
constexpr std::uint32_t kLeavesWord = 2 * kMaxPasses;
constexpr std::uint32_t kTrianglesWord = 2 * kMaxPasses + 1;
constexpr std::uint32_t kCounterWords = 2 * kMaxPasses + 2;
constexpr std::uint32_t kDispatchWord = 2 * kMaxPasses + 4;  // 16-byte aligned
constexpr std::uint32_t kSplitSlot = 0;                      // + pass
constexpr std::uint32_t kLeavesSlot = kMaxPasses;            // the pass from the leaves
constexpr std::uint32_t kPendingSlot = kMaxPasses + 1;       // + pass
constexpr std::uint32_t kDrawWord = kDispatchWord + 4 * (2 * kMaxPasses + 1);
constexpr std::uint32_t kTotalWords = kDrawWord + 4;

constexpr std::uint32_t slotWord(std::uint32_t slot) { return kDispatchWord + 4 * slot; }

constexpr std::size_t kBlockBytes = 2 * sizeof(std::int32_t);     // ivec2
constexpr std::size_t kLeafBytes = 4 * sizeof(std::int32_t);      // ivec4
constexpr std::size_t kPendingBytes = 8 * sizeof(std::int32_t);   // two ivec4
constexpr std::size_t kTriangleBytes = 6 * sizeof(std::int32_t);  // three ivec2

/// The GPU's textures: the height field, the quadtree texture and ranges, the split flags
/// (one byte a sample of the n × n grid).
std::size_t textureBytesFor(int width, int height) {
    const auto side = (std::size_t{1} << RoughnessQuadtree::depthFor(width, height)) + 1;
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * sizeof(float) +
           RoughnessQuadtree::bytesFor(width, height) + side * side;
}

Result<gl::Program> buildProgram(std::string label, std::initializer_list<std::string> stages,
                                 bool fromLeaves = false) {
    ProgramBuilder builder(std::move(label));
    for (const std::string& s : stages) builder.stage(s);
    builder.define("LEE_MAX_PASSES", std::to_string(kMaxPasses))
        .define("LEE_FORCE_SPLIT", fmt::format("{:.1e}", RoughnessQuadtree::kForceSplit));
    if (fromLeaves) builder.define("LEE_FROM_LEAVES");
    return builder.build();
}

std::uint32_t grown(std::uint32_t capacity, std::uint64_t needed) {
    const std::uint64_t target = std::max<std::uint64_t>(2ull * capacity, needed + needed / 4);
    return static_cast<std::uint32_t>(std::min<std::uint64_t>(std::bit_ceil(target), 1u << 31));
}

}  // namespace

Result<std::unique_ptr<GeometrySplittingStrategy>> GeometrySplittingStrategy::open(
    const std::filesystem::path& pyramid, double errorPx, std::size_t maxBytes) {
    auto reader = openPlanarPyramid(pyramid, "Lee & Shin's GPU quadtree");
    if (!reader) return reader.error();
    const io::PyramidManifest& manifest = reader.value().manifest();
    const auto width = static_cast<int>(manifest.layout.rasterWidth());
    const auto height = static_cast<int>(manifest.layout.rasterHeight());
    // Refused before a sample is read when it would not fit.
    if (const std::size_t need = textureBytesFor(width, height); need > maxBytes)
        return Error{fmt::format(
            "{}: {} × {} samples need {} MiB of height field, quadtree texture and flags on the "
            "GPU, over the {} MiB this method may hold (it keeps the whole finest level "
            "in core, as the paper does)",
            pyramid.string(), width, height, need >> 20, maxBytes >> 20)};
    auto raster = readFinestLevel(reader.value());
    if (!raster) return Error{pyramid.string() + ": " + raster.error().message};
    auto strategy = create(manifest, std::move(raster).value(), errorPx, maxBytes);
    if (!strategy) return Error{pyramid.string() + ": " + strategy.error().message};
    return strategy;
}

Result<std::unique_ptr<GeometrySplittingStrategy>> GeometrySplittingStrategy::create(
    const io::PyramidManifest& manifest, std::vector<float> heights, double errorPx,
    std::size_t maxBytes) {
    const auto width = static_cast<int>(manifest.layout.rasterWidth());
    const auto height = static_cast<int>(manifest.layout.rasterHeight());
    if (const std::size_t need = textureBytesFor(width, height); need > maxBytes)
        return Error{fmt::format("{} × {} samples need {} MiB on the GPU, over the {} MiB allowed",
                                 width, height, need >> 20, maxBytes >> 20)};
    auto tree = RoughnessQuadtree::build(width, height, heights);
    if (!tree) return tree.error();
    if (tree.value().depth() + 1 >= static_cast<int>(kMaxPasses))
        return Error{"the raster is too large for the quadtree's passes"};

    Programs programs;
    auto split = buildProgram("lee split", {"lee_split.comp"});
    if (!split) return split.error();
    auto fromLeaves = buildProgram("lee leaves", {"lee_triangles.comp"}, true);
    if (!fromLeaves) return fromLeaves.error();
    auto splitTriangles = buildProgram("lee triangles", {"lee_triangles.comp"});
    if (!splitTriangles) return splitTriangles.error();
    auto arguments = buildProgram("lee arguments", {"lee_arguments.comp"});
    if (!arguments) return arguments.error();
    auto draw = buildProgram("lee draw", {"lee_draw.vert", "reference.frag"});
    if (!draw) return draw.error();
    programs.split = std::move(split).value();
    programs.fromLeaves = std::move(fromLeaves).value();
    programs.splitTriangles = std::move(splitTriangles).value();
    programs.arguments = std::move(arguments).value();
    programs.draw = std::move(draw).value();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "lee GPU time");
    if (!time) return time.error();

    std::unique_ptr<GeometrySplittingStrategy> strategy(new GeometrySplittingStrategy(
        manifest, std::move(programs), std::move(time).value(), errorPx, maxBytes));
    if (auto uploaded = strategy->upload(tree.value(), heights); !uploaded) return uploaded.error();
    if (auto lists = strategy->allocateLists(); !lists) return lists.error();
    return strategy;
}

GeometrySplittingStrategy::GeometrySplittingStrategy(const io::PyramidManifest& manifest,
                                                     Programs programs, gl::Query timeQuery,
                                                     double errorPx, std::size_t maxBytes)
    : m_surface(std::make_unique<PlaneSurface>(manifest)),
      m_frame(m_surface->geometry(), "lee frame"),
      m_programs(std::move(programs)),
      m_timeQuery(std::move(timeQuery)),
      m_emptyVertexArray(gl::VertexArray::create("lee draw (no attributes)")),
      m_thresholdPx(errorPx),
      m_maxBytes(maxBytes) {}

GeometrySplittingStrategy::~GeometrySplittingStrategy() = default;

Status GeometrySplittingStrategy::upload(const RoughnessQuadtree& tree,
                                         const std::vector<float>& heights) {
    m_depth = tree.depth();
    m_side = tree.side();
    const int width = tree.width(), height = tree.height();
    auto heightField = gl::Texture::create2D({GL_R32F, width, height, 1, 1}, "lee height field");
    if (!heightField) return heightField.error();
    m_heights = std::move(heightField).value();
    m_heights.upload({0, 0, 0, 0, width, height, 1}, GL_RED, GL_FLOAT,
                     std::as_bytes(std::span(heights)));

    auto roughness = gl::Texture::create2D({GL_R32F, m_side, m_side, 1, 1}, "lee quadtree texture");
    if (!roughness) return roughness.error();
    m_roughness = std::move(roughness).value();
    m_roughness.upload({0, 0, 0, 0, m_side, m_side, 1}, GL_RED, GL_FLOAT,
                       std::as_bytes(std::span(tree.roughness())));

    const int finestBlocks = tree.blocksPerSide(0);
    auto ranges = gl::Texture::create2D({GL_RG32F, finestBlocks, finestBlocks, 1, m_depth},
                                        "lee block height ranges");
    if (!ranges) return ranges.error();
    m_ranges = std::move(ranges).value();
    for (int level = 0; level < m_depth; ++level) {
        const int blocks = tree.blocksPerSide(level);
        m_ranges.upload({level, 0, 0, 0, blocks, blocks, 1}, GL_RG, GL_FLOAT,
                        std::as_bytes(std::span(tree.heightRange(level))));
    }

    auto flags = gl::Texture::create2D({GL_R8UI, m_side, m_side, 1, 1}, "lee split flags");
    if (!flags) return flags.error();
    m_splitFlags = std::move(flags).value();
    m_textureBytes = textureBytesFor(width, height);

    const std::vector<std::uint32_t> zeros(kTotalWords, 0u);
    m_counters = gl::Buffer::create(kTotalWords * sizeof(std::uint32_t), GL_DYNAMIC_STORAGE_BIT,
                                    "lee counters and arguments", zeros.data());
    return {};
}

Status GeometrySplittingStrategy::allocateLists() {
    const Capacities& c = m_capacities;
    const std::size_t bytes = 2 * c.blocks * kBlockBytes + c.leaves * kLeafBytes +
                              2 * c.pending * kPendingBytes + c.triangles * kTriangleBytes;
    if (m_textureBytes + bytes > m_maxBytes)
        return Error{fmt::format(
            "this view needs {:.1f} MiB of quadtree lists and textures, over the {:.1f} MiB "
            "Lee & Shin's method may hold",
            static_cast<double>(m_textureBytes + bytes) / (1 << 20),
            static_cast<double>(m_maxBytes) / (1 << 20))};
    constexpr GLbitfield kGpuOnly = 0;
    // The first pass's input is written from the CPU (the root), the rest only by the GPU.
    m_blocks[0] = gl::Buffer::create(c.blocks * kBlockBytes, GL_DYNAMIC_STORAGE_BIT, "lee blocks");
    m_blocks[1] = gl::Buffer::create(c.blocks * kBlockBytes, kGpuOnly, "lee blocks");
    for (gl::Buffer& pending : m_pending)
        pending = gl::Buffer::create(c.pending * kPendingBytes, kGpuOnly, "lee pending");
    m_leaves = gl::Buffer::create(c.leaves * kLeafBytes, kGpuOnly, "lee leaves");
    m_triangles = gl::Buffer::create(c.triangles * kTriangleBytes, kGpuOnly, "lee triangles");
    return {};
}

void GeometrySplittingStrategy::setMethodUniforms(gl::Program& program) const {
    program.setUniform(
        "u_rasterSize",
        std::array<int, 2>{static_cast<int>(m_surface->geometry().layout().rasterWidth()),
                           static_cast<int>(m_surface->geometry().layout().rasterHeight())});
    program.setUniform("u_gridSide", m_side);
    program.setUniform("u_thresholdPx", static_cast<float>(m_thresholdPx));
}

void GeometrySplittingStrategy::writeArguments(std::uint32_t countWord, std::uint32_t capacity,
                                               std::uint32_t argumentsWord, bool draw) {
    gl::Program& program = m_programs.arguments;
    program.setUniform("u_countWord", countWord);
    program.setUniform("u_capacity", capacity);
    program.setUniform("u_argumentsWord", argumentsWord);
    program.setUniform("u_draw", draw ? 1 : 0);
    glUseProgram(program.id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

bool GeometrySplittingStrategy::build(const Camera& camera) {
    const Capacities& cap = m_capacities;
    // The root alone enters the first pass; every flag is cleared.
    const std::uint32_t zero = 0;
    glClearNamedBufferSubData(m_counters.id(), GL_R32UI, 0, kCounterWords * sizeof(std::uint32_t),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    const std::uint32_t one = 1;
    m_counters.upload(kNodesWord * sizeof(std::uint32_t), std::as_bytes(std::span(&one, 1)));
    const std::int32_t rootHalf = 1 << (m_depth - 1);
    const std::array<std::int32_t, 2> root{rootHalf, rootHalf};
    m_blocks[0].upload(0, std::as_bytes(std::span(root)));
    const std::uint8_t noFlag = 0;
    glClearTexImage(m_splitFlags.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &noFlag);

    m_frame.bind(camera, TerrainStyle{}, m_thresholdPx);
    for (gl::Program* p : {&m_programs.split, &m_programs.fromLeaves, &m_programs.splitTriangles})
        setMethodUniforms(*p);
    glBindTextureUnit(TERRAIN_BINDING_LEE_HEIGHTS, m_heights.id());
    glBindTextureUnit(TERRAIN_BINDING_LEE_ROUGHNESS, m_roughness.id());
    glBindTextureUnit(TERRAIN_BINDING_LEE_RANGES, m_ranges.id());
    glBindImageTexture(TERRAIN_IMAGE_LEE_SPLIT_FLAGS, m_splitFlags.id(), 0, GL_FALSE, 0,
                       GL_READ_WRITE, GL_R8UI);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_COUNTERS, m_counters.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_LEAVES, m_leaves.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_TRIANGLES, m_triangles.id());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, m_counters.id());
    glMemoryBarrier(GL_ALL_BARRIER_BITS);

    const auto dispatch = [](std::uint32_t slot) {
        glDispatchComputeIndirect(static_cast<GLintptr>(slotWord(slot) * sizeof(std::uint32_t)));
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_COMMAND_BARRIER_BIT);
    };
    // Vertex splitting (§2.3): pass p takes the blocks of level d − 1 − p.
    gl::Program& split = m_programs.split;
    split.setUniform("u_blockCapacity", cap.blocks);
    split.setUniform("u_leafCapacity", cap.leaves);
    for (int pass = 0; pass < m_depth; ++pass) {
        const int level = m_depth - 1 - pass;
        writeArguments(kNodesWord + pass, cap.blocks, slotWord(kSplitSlot + pass), false);
        split.setUniform("u_pass", pass);
        split.setUniform("u_level", level);
        split.setUniform("u_halfSize", 1 << level);
        glUseProgram(split.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_INPUT,
                         m_blocks[pass % 2].id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_OUTPUT,
                         m_blocks[(pass + 1) % 2].id());
        dispatch(kSplitSlot + pass);
    }
    // Triangle splitting (§2.4): the leaves' triangles, then one level of T-vertices a pass.
    writeArguments(kLeavesWord, cap.leaves, slotWord(kLeavesSlot), false);
    gl::Program& fromLeaves = m_programs.fromLeaves;
    fromLeaves.setUniform("u_pass", -1);
    fromLeaves.setUniform("u_leafCapacity", cap.leaves);
    fromLeaves.setUniform("u_pendingCapacity", cap.pending);
    fromLeaves.setUniform("u_triangleCapacity", cap.triangles);
    glUseProgram(fromLeaves.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_OUTPUT, m_pending[0].id());
    dispatch(kLeavesSlot);
    gl::Program& splitTriangles = m_programs.splitTriangles;
    splitTriangles.setUniform("u_pendingCapacity", cap.pending);
    splitTriangles.setUniform("u_triangleCapacity", cap.triangles);
    for (int pass = 0; pass < m_depth; ++pass) {
        writeArguments(kPendingWord + pass, cap.pending, slotWord(kPendingSlot + pass), false);
        splitTriangles.setUniform("u_pass", pass);
        glUseProgram(splitTriangles.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_INPUT,
                         m_pending[pass % 2].id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_OUTPUT,
                         m_pending[(pass + 1) % 2].id());
        dispatch(kPendingSlot + pass);
    }
    writeArguments(kTrianglesWord, cap.triangles, kDrawWord, true);
    glUseProgram(0);
    PlaneFrame::unbind();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    for (GLuint binding :
         {TERRAIN_BINDING_LEE_COUNTERS, TERRAIN_BINDING_LEE_INPUT, TERRAIN_BINDING_LEE_OUTPUT,
          TERRAIN_BINDING_LEE_LEAVES, TERRAIN_BINDING_LEE_TRIANGLES})
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, 0);
    glBindImageTexture(TERRAIN_IMAGE_LEE_SPLIT_FLAGS, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8UI);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    // The counters, to report and to find a list that overflowed.
    std::array<std::uint32_t, kCounterWords> words{};
    m_counters.readBack(0, std::as_writable_bytes(std::span(words)));
    Capacities next = cap;
    m_counts.blocksEvaluated = 0;
    for (std::uint32_t p = 0; p < kMaxPasses; ++p) {
        m_counts.blocksEvaluated += std::min(words[kNodesWord + p], cap.blocks);
        if (words[kNodesWord + p] > cap.blocks)
            next.blocks = std::max(next.blocks, grown(cap.blocks, words[kNodesWord + p]));
        if (words[kPendingWord + p] > cap.pending)
            next.pending = std::max(next.pending, grown(cap.pending, words[kPendingWord + p]));
    }
    if (words[kLeavesWord] > cap.leaves) next.leaves = grown(cap.leaves, words[kLeavesWord]);
    if (words[kTrianglesWord] > cap.triangles)
        next.triangles = grown(cap.triangles, words[kTrianglesWord]);
    m_counts.leaves = std::min(words[kLeavesWord], cap.leaves);
    m_counts.triangles = std::min(words[kTrianglesWord], cap.triangles);
    m_needed = next;
    return next.blocks == cap.blocks && next.leaves == cap.leaves && next.pending == cap.pending &&
           next.triangles == cap.triangles;
}

const LodUpdateStats& GeometrySplittingStrategy::beginFrame(const Camera& camera) {
    const auto start = Clock::now();
    m_counts.builds = 0;
    bool complete = false;
    // Each build that overflows grows a list at least twofold; past the memory budget the
    // frame draws what fitted, and says so once.
    while (!complete) {
        ++m_counts.builds;
        complete = build(camera);
        if (complete) break;
        const Capacities fitted = m_capacities;
        m_capacities = m_needed;
        if (auto lists = allocateLists(); !lists) {
            m_capacities = fitted;  // the lists that exist
            if (!m_warnedOverBudget)
                fmt::print(stderr, "lee2011: {}; drawing what fits\n", lists.error().message);
            m_warnedOverBudget = true;
            break;
        }
    }
    m_lodUpdateUs = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    m_stats = {};
    m_stats.evaluations = m_counts.blocksEvaluated;
    m_stats.nodes = m_counts.blocksEvaluated;
    m_stats.drawn = m_counts.leaves;
    m_lastDraw = {};
    return m_stats;
}

TerrainDrawStats GeometrySplittingStrategy::draw(const Camera& camera, const TerrainStyle& style) {
    gl::Program& program = m_programs.draw;
    m_frame.bind(camera, style, m_thresholdPx);
    setMethodUniforms(program);
    TerrainDrawStats stats;
    stats.drawCalls = 1;
    stats.instances = 1;
    stats.triangles = m_counts.triangles;
    glBindTextureUnit(TERRAIN_BINDING_LEE_HEIGHTS, m_heights.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_TRIANGLES, m_triangles.id());
    stats.gpuMs = drawTrianglesIndirect(program, m_emptyVertexArray, m_counters,
                                        kDrawWord * sizeof(std::uint32_t), m_timeQuery, style);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_LEE_TRIANGLES, 0);
    PlaneFrame::unbind();
    m_lastDraw = stats;
    return stats;
}

void GeometrySplittingStrategy::endFrame(FrameTelemetry& t) {
    writeDrawTelemetry(t, m_lodUpdateUs, m_lastDraw);
}

std::uint64_t GeometrySplittingStrategy::memoryBytes() const {
    return m_textureBytes + m_counters.sizeBytes() + m_blocks[0].sizeBytes() +
           m_blocks[1].sizeBytes() + m_pending[0].sizeBytes() + m_pending[1].sizeBytes() +
           m_leaves.sizeBytes() + m_triangles.sizeBytes();
}

std::vector<std::array<glm::ivec2, 3>> GeometrySplittingStrategy::readTriangles() const {
    std::vector<std::int32_t> words(m_counts.triangles * 6);
    if (!words.empty()) {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        m_triangles.readBack(0, std::as_writable_bytes(std::span(words)));
    }
    std::vector<std::array<glm::ivec2, 3>> triangles(m_counts.triangles);
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (std::size_t v = 0; v < 3; ++v)
            triangles[t][v] = {words[6 * t + 2 * v], words[6 * t + 2 * v + 1]};
    return triangles;
}

}  // namespace terrain::runtime
