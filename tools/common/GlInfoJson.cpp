#include "GlInfoJson.h"

namespace terrain::tools {

nlohmann::json glInfoJson(const gl::GlContext& context) {
    const gl::GlInfo& info = context.info();
    const gl::DriverWorkaroundsApplied& applied = context.driverWorkarounds();
    return {
        {"platform", info.platform},
        {"platformDetail", info.platformDetail},
        {"vendor", info.vendor},
        {"renderer", info.renderer},
        {"version", info.version},
        {"glslVersion", info.glslVersion},
        {"major", info.major},
        {"minor", info.minor},
        {"coreProfile", info.coreProfile},
        {"debugContext", info.debugContext},
        {"maxTessGenLevel", info.maxTessGenLevel},
        {"maxTextureSize", info.maxTextureSize},
        {"maxArrayTextureLayers", info.maxArrayTextureLayers},
        {"maxTextureAnisotropy", info.maxTextureAnisotropy},
        {"driverWorkarounds",
         {{"llvmpipeHeapTrimOff", applied.llvmpipeHeapTrimOff},
          {"driModulePinnedForLeakChecks", applied.driModulePinnedForLeakChecks},
          {"genQueriesForPipelineStatistics", gl::kGenQueriesForPipelineStatistics}}},
    };
}

}  // namespace terrain::tools
