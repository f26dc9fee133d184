// Query: one GL query object of a fixed kind (primitives generated, GPU time, tessellation
// evaluation invocations); results are read as 64-bit integers.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Handle.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace terrain::gl {

enum class QueryKind {
    PrimitivesGenerated,        ///< GL_PRIMITIVES_GENERATED (vertex stream 0)
    TimeElapsed,                ///< GL_TIME_ELAPSED, nanoseconds
    TessEvaluationInvocations,  ///< GL 4.6 or GL_ARB_pipeline_statistics_query
};

class Query {
public:
    Query() = default;

    /// Whether the current context supports `kind`. Render thread only.
    static bool isSupported(QueryKind kind);

    /// An Error when the current context does not support `kind`. Render thread only.
    static Result<Query> create(QueryKind kind, std::string_view label = {});

    /// glBeginQuery / glEndQuery on this query's target; at most one active query per
    /// target, as GL requires. Render thread only.
    void begin();
    void end();

    /// True once the result can be read without waiting. Render thread only.
    bool resultAvailable() const;

    /// The result, waiting for the GPU if needed. Render thread only.
    std::uint64_t waitResult() const;

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }
    QueryKind kind() const { return m_kind; }
    GLenum target() const { return m_target; }
    bool active() const { return m_active; }

private:
    QueryHandle m_handle;
    QueryKind m_kind = QueryKind::PrimitivesGenerated;
    GLenum m_target = GL_NONE;
    bool m_active = false;
    std::string m_pendingLabel;  ///< applied at the first begin(), see DriverWorkarounds.h
};

}  // namespace terrain::gl
