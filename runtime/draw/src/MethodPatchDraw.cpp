// MethodPatchDraw: program, queries, instance records.
#include "terrain/runtime/MethodPatchDraw.h"

#include "terrain/base/Assert.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/SurfacePlacement.h"

#include <epoxy/gl.h>

namespace terrain::runtime {

Result<MethodPatchDraw> MethodPatchDraw::create(const std::string& name,
                                                std::initializer_list<const char*> stages,
                                                int maxInstances) {
    TERRAIN_ASSERT(maxInstances >= 1);
    ProgramBuilder builder(name);
    for (const char* stage : stages) builder.stage(stage);
    auto program = builder.build();
    if (!program) return program.error();
    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, name + " triangles");
    if (!primitives) return primitives.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, name + " GPU time");
    if (!time) return time.error();
    MethodPatchDraw d;
    d.program = std::move(program).value();
    d.primitivesQuery = std::move(primitives).value();
    d.timeQuery = std::move(time).value();
    d.vertexArray = gl::VertexArray::create(name + " (attribute-less)");
    d.instances = gl::Buffer::create(sizeof(PatchInstance) * static_cast<std::size_t>(maxInstances),
                                     GL_DYNAMIC_STORAGE_BIT, name + " patch instances");
    d.frameBuffer = FrameBlockBuffer::create(name + " frame block");
    d.staging.reserve(static_cast<std::size_t>(maxInstances));
    d.maxInstances = maxInstances;
    return d;
}

void MethodPatchDraw::prepare(const Camera& camera, const TerrainGeometry& geometry,
                              const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                              const TerrainStyle& style, double errorPx) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(maxInstances),
                   "MethodPatchDraw: more patches than instances");
    PlanePlacement placement(geometry);
    placement.beginFrame(camera, frame);
    staging.clear();
    for (const PatchDraw& patch : patches) staging.push_back(placement.place(patch, pool));
    instances.upload(0, std::as_bytes(std::span(staging)));
    setCameraFrame(frame, camera, camera, errorPx);
    setLook(frame, style);
}

}  // namespace terrain::runtime
