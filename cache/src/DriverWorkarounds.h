// Driver workarounds of the GL wrappers, collected in one place, each with its reason.
// A workaround stays until every driver the project supports no longer needs it.
#pragma once

namespace terrain::gl::detail {

/// Mesa 22.3 (llvmpipe and others) rejects the pipeline-statistics targets of
/// GL_ARB_pipeline_statistics_query in glCreateQueries with GL_INVALID_ENUM, although
/// glBeginQuery accepts them. For those targets Query names come from glGenQueries and
/// the object (and its debug label) comes into being at the first glBeginQuery.
inline constexpr bool kGenQueriesForPipelineStatistics = true;

}  // namespace terrain::gl::detail
