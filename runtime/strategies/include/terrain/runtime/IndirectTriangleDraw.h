// drawTrianglesIndirect: the draw of the methods whose triangles the GPU wrote itself (Lee &
// Shin, Ripolles): one glDrawArraysIndirect of GL_TRIANGLES with no vertex attributes (the
// vertex stage reads the triangles from a storage buffer the caller has bound), in the
// terrain's reversed-Z depth state, as lines for style.wireframe, timed for style.measure.
#pragma once

#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Query.h"
#include "terrain/gl/VertexArray.h"
#include "terrain/runtime/TerrainRenderer.h"

#include <cstddef>

namespace terrain::runtime {

/// The GPU milliseconds of the draw when style.measure (timed with `timer`), else 0.
/// `arguments` holds a DrawArraysIndirectCommand at `offsetBytes`. Render thread only.
double drawTrianglesIndirect(const gl::Program& program, const gl::VertexArray& noAttributes,
                             const gl::Buffer& arguments, std::size_t offsetBytes, gl::Query& timer,
                             const TerrainStyle& style);

}  // namespace terrain::runtime
