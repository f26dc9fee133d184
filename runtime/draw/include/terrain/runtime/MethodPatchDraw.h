// MethodPatchDraw: what the comparison methods' renderers (ValdetaroRenderer, LivnyRenderer,
// CdlodRenderer) share: their program, the queries that measure a draw, an attribute-less
// vertex array and the per-patch instance records, written relative to the camera's anchor
// with the frame's camera and shading uniforms. Each renderer adds its own uniforms and
// issues its own draw call.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/cache/GpuTilePool.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/PatchInstanceRecord.h"
#include "terrain/runtime/PatchSelection.h"
#include "terrain/runtime/TerrainGeometry.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <initializer_list>
#include <span>
#include <string>
#include <vector>

namespace terrain::runtime {

struct MethodPatchDraw {
    gl::Program program;
    gl::VertexArray vertexArray;
    gl::Buffer instances;
    gl::Query primitivesQuery;
    gl::Query timeQuery;
    std::vector<PatchInstanceRecord> staging;
    int maxInstances = 0;

    /// Builds `name`'s program from `stages` (shaders/) and room for `maxInstances` patches.
    static Result<MethodPatchDraw> create(const std::string& name,
                                          std::initializer_list<const char*> stages,
                                          int maxInstances);

    /// Writes and uploads the records of `patches` and sets the camera frame, shading and
    /// debug-view uniforms for `camera` and `style`.
    void prepare(const Camera& camera, const TerrainGeometry& geometry,
                 const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                 const TerrainStyle& style);

    /// The queries to measure a draw with when the style asks (null otherwise).
    gl::Query* primitivesIf(const TerrainStyle& style) {
        return style.measure ? &primitivesQuery : nullptr;
    }
    gl::Query* timeIf(const TerrainStyle& style) { return style.measure ? &timeQuery : nullptr; }
};

}  // namespace terrain::runtime
