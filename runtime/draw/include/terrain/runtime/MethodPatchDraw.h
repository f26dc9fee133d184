// MethodPatchDraw: what the comparison methods' renderers (ValdetaroRenderer, LivnyRenderer,
// CdlodRenderer; planar only) share: their program, the queries that measure a draw, an
// attribute-less vertex array, the per-patch instance records placed on the plane
// (PlanePlacement) and the frame block with the frame's camera, placement and look. Each
// renderer adds its tessellation grid and its own uniforms, and issues its own draw call.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FrameBlock.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/PatchInstance.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainStyle.h"

#include <initializer_list>
#include <span>
#include <string>
#include <vector>

namespace terrain::runtime {

struct MethodPatchDraw {
    gl::Program program;
    gl::VertexArray vertexArray;
    gl::Buffer instances;
    FrameBlockBuffer frameBuffer;
    gl::Query primitivesQuery;
    gl::Query timeQuery;
    std::vector<PatchInstance> staging;
    FrameBlock frame;
    int maxInstances = 0;

    /// Builds `name`'s program from `stages` (shaders/) and room for `maxInstances` patches.
    static Result<MethodPatchDraw> create(const std::string& name,
                                          std::initializer_list<const char*> stages,
                                          int maxInstances);

    /// Writes and uploads the records of `patches` and fills the frame block's camera,
    /// placement and look for `camera` and `style` at ε = `errorPx`; the renderer adds its
    /// tessellation grid (setTessellation) and calls uploadFrame().
    void prepare(const Camera& camera, const TerrainGeometry& geometry,
                 const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                 const TerrainStyle& style, double errorPx);
    void uploadFrame() { frameBuffer.upload(frame); }

    /// The queries to measure a draw with when the style asks (null otherwise).
    gl::Query* primitivesIf(const TerrainStyle& style) {
        return style.measure ? &primitivesQuery : nullptr;
    }
    gl::Query* timeIf(const TerrainStyle& style) { return style.measure ? &timeQuery : nullptr; }
};

}  // namespace terrain::runtime
