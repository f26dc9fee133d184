// Query objects; results are read into client memory even if a query buffer is bound.
#include "terrain/gl/Query.h"

#include "terrain/base/Assert.h"
#include "terrain/gl/DriverWorkarounds.h"

#include <string>
#include <utility>

namespace terrain::gl {
namespace {

GLenum queryTarget(QueryKind kind) {
    switch (kind) {
        case QueryKind::PrimitivesGenerated:
            return GL_PRIMITIVES_GENERATED;
        case QueryKind::TimeElapsed:
            return GL_TIME_ELAPSED;
        case QueryKind::TessEvaluationInvocations:
            return GL_TESS_EVALUATION_SHADER_INVOCATIONS;
    }
    return GL_NONE;
}

const char* queryName(QueryKind kind) {
    switch (kind) {
        case QueryKind::PrimitivesGenerated:
            return "GL_PRIMITIVES_GENERATED";
        case QueryKind::TimeElapsed:
            return "GL_TIME_ELAPSED";
        case QueryKind::TessEvaluationInvocations:
            return "GL_TESS_EVALUATION_SHADER_INVOCATIONS";
    }
    return "unknown query";
}

/// glGetQueryObjectui64v writes into the bound GL_QUERY_BUFFER when there is one; unbind
/// it for the read and put it back, so the pointer is always client memory.
std::uint64_t readQueryObject(GLuint id, GLenum parameter) {
    GLint savedQueryBuffer = 0;
    glGetIntegerv(GL_QUERY_BUFFER_BINDING, &savedQueryBuffer);
    if (savedQueryBuffer != 0) {
        glBindBuffer(GL_QUERY_BUFFER, 0);
    }
    GLuint64 value = 0;
    glGetQueryObjectui64v(id, parameter, &value);
    if (savedQueryBuffer != 0) {
        glBindBuffer(GL_QUERY_BUFFER, static_cast<GLuint>(savedQueryBuffer));
    }
    return value;
}

}  // namespace

bool Query::isSupported(QueryKind kind) {
    switch (kind) {
        case QueryKind::PrimitivesGenerated:
        case QueryKind::TimeElapsed:
            return true;  // core since GL 3.3
        case QueryKind::TessEvaluationInvocations:
            return epoxy_gl_version() >= 46 ||
                   epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query");
    }
    return false;
}

Result<Query> Query::create(QueryKind kind, std::string_view label) {
    if (!isSupported(kind)) {
        return Error{std::string("query '") + std::string(label) + "': " + queryName(kind) +
                     " needs OpenGL 4.6 or GL_ARB_pipeline_statistics_query"};
    }
    Query query;
    query.m_kind = kind;
    query.m_target = queryTarget(kind);
    GLuint id = 0;
    if (kGenQueriesForPipelineStatistics && kind == QueryKind::TessEvaluationInvocations) {
        glGenQueries(1, &id);
        query.m_handle = QueryHandle(id);
        query.m_pendingLabel = std::string(label);  // a name without an object takes none
    } else {
        glCreateQueries(query.m_target, 1, &id);
        query.m_handle = QueryHandle(id);
        query.m_handle.setLabel(label);
    }
    return query;
}

void Query::begin() {
    TERRAIN_ASSERT(valid());
    TERRAIN_ASSERT(!m_active, "Query::begin on an active query");
    glBeginQuery(m_target, id());
    m_active = true;
    if (!m_pendingLabel.empty()) {
        m_handle.setLabel(m_pendingLabel);
        m_pendingLabel.clear();
    }
}

void Query::end() {
    TERRAIN_ASSERT(m_active, "Query::end without begin");
    glEndQuery(m_target);
    m_active = false;
}

bool Query::resultAvailable() const {
    TERRAIN_ASSERT(valid() && !m_active);
    return readQueryObject(id(), GL_QUERY_RESULT_AVAILABLE) != 0;
}

std::uint64_t Query::waitResult() const {
    TERRAIN_ASSERT(valid() && !m_active);
    return readQueryObject(id(), GL_QUERY_RESULT);
}

}  // namespace terrain::gl
