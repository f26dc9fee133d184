// drawTrianglesIndirect: the state set for the draw and set back after it.
#include "terrain/runtime/IndirectTriangleDraw.h"

#include "terrain/gl/ReversedZScope.h"

#include <epoxy/gl.h>

#include <cstdint>

namespace terrain::runtime {

double drawTrianglesIndirect(const gl::Program& program, const gl::VertexArray& noAttributes,
                             const gl::Buffer& arguments, std::size_t offsetBytes, gl::Query& timer,
                             const TerrainStyle& style) {
    const gl::ReversedZScope reversedZ;
    if (style.wireframe) glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glUseProgram(program.id());
    glBindVertexArray(noAttributes.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, arguments.id());
    if (style.measure) timer.begin();
    glDrawArraysIndirect(GL_TRIANGLES,
                         reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offsetBytes)));
    double gpuMs = 0.0;
    if (style.measure) {
        timer.end();
        gpuMs = static_cast<double>(timer.waitResult()) * 1.0e-6;
    }
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindVertexArray(0);
    glUseProgram(0);
    if (style.wireframe) glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    return gpuMs;
}

}  // namespace terrain::runtime
