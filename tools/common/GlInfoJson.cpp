#include "GlInfoJson.h"

namespace terrain::tools {

nlohmann::json glInfoJson(const gl::GlInfo& info) {
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
    };
}

}  // namespace terrain::tools
