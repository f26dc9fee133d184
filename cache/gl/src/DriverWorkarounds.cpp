// DriverWorkarounds: per-driver adjustments, keyed on the GL renderer string and the build.
#include "terrain/gl/DriverWorkarounds.h"

#include <epoxy/gl.h>

#include <dlfcn.h>
#include <link.h>
#include <malloc.h>

#include <limits>
#include <string_view>

namespace terrain::gl {
namespace {

#if defined(__SANITIZE_ADDRESS__)
int pinDriModule(struct dl_phdr_info* info, std::size_t, void* pinned) {
    const std::string_view path = info->dlpi_name != nullptr ? info->dlpi_name : "";
    if (path.find("/dri/") == std::string_view::npos || !path.ends_with("_dri.so")) return 0;
    // RTLD_NOLOAD: only a module already loaded; RTLD_NODELETE: never unloaded afterwards.
    if (void* handle = dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE)) {
        dlclose(handle);
        *static_cast<bool*>(pinned) = true;
    }
    return 0;
}
#endif

}  // namespace

float textureAnisotropyWorthFiltering() {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (renderer != nullptr &&
        std::string_view(renderer).find("llvmpipe") != std::string_view::npos)
        return 1.0f;
    return maxTextureAnisotropy();
}

DriverWorkaroundsApplied applyDriverWorkarounds(const GlInfo& info) {
    DriverWorkaroundsApplied applied;
    if (info.renderer.find("llvmpipe") != std::string::npos) {
        // 2 GiB, the most mallopt takes: more than a frame frees at the heap's top.
        applied.llvmpipeHeapTrimOff =
            mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max()) != 0;
    }
#if defined(__SANITIZE_ADDRESS__)
    dl_iterate_phdr(&pinDriModule, &applied.driModulePinnedForLeakChecks);
#endif
    return applied;
}

}  // namespace terrain::gl
