// DriverWorkarounds: the one place where the project works around a GL driver's or a system
// library's behaviour, each workaround with its reason and the measurement or report that
// justified it. A workaround stays until every driver the project supports no longer needs
// it. Process-wide ones are applied by both context classes (applyDriverWorkarounds, once
// their context is current); the GL wrappers read the constants below.
#pragma once

#include "terrain/gl/GlInfo.h"

namespace terrain::gl {

/// Mesa 22.3 (llvmpipe and others) rejects the pipeline-statistics targets of
/// GL_ARB_pipeline_statistics_query in glCreateQueries with GL_INVALID_ENUM, although
/// glBeginQuery accepts them. For those targets Query names come from glGenQueries and
/// the object (and its debug label) comes into being at the first glBeginQuery (Query.cpp).
inline constexpr bool kGenQueriesForPipelineStatistics = true;

/// The anisotropy worth filtering with in the current context: maxTextureAnisotropy(), but 1
/// (trilinear) on llvmpipe, which runs the anisotropic filter sample by sample in its
/// fragment code. terrain-render planet: --width 480 --height 270 --frames 40 took 272 s
/// with the imagery sampled at up to 16× (not finished in 300 s when drawn), 36 s at 1×,
/// 29 s without imagery (2 cores). Render thread only.
float textureAnisotropyWorthFiltering();

/// What applyDriverWorkarounds() did, for tools' --json (GlContext::driverWorkarounds()).
struct DriverWorkaroundsApplied {
    /// llvmpipe: glibc no longer trims the heap (M_TRIM_THRESHOLD raised to 2 GiB). Mesa's
    /// software tessellator allocates its vertex output per draw from the heap and frees
    /// it; glibc then returned the heap's top to the kernel after every frame, and the next
    /// frame page-faulted it all back in: a third of a terrain frame in the kernel (perf),
    /// and 108 → 29 ms per frame of terrain-stress --flight cruise at 480×270, ε = 0.5 px
    /// over the Puget Sound 4K pyramid. Memory stays at its high-water mark instead.
    bool llvmpipeHeapTrimOff = false;
    /// AddressSanitizer builds: the loaded Mesa DRI driver (e.g. swrast_dri.so) is never
    /// unloaded. It keeps a few blocks reachable only from its own globals, and GLFW's
    /// glfwTerminate unloads it when the X display closes, so LeakSanitizer reported them
    /// at exit with stack frames in a module that is gone (no suppression can name it).
    /// Pinned, the driver lives as long as the process, as it does behind EGL anyway.
    bool driModulePinnedForLeakChecks = false;
};

/// Applies what `info`'s driver needs; process-wide, idempotent. Render thread, with the
/// context current.
DriverWorkaroundsApplied applyDriverWorkarounds(const GlInfo& info);

}  // namespace terrain::gl
