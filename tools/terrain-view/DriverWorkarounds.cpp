// Driver and system-library workarounds of the viewer.
#include "DriverWorkarounds.h"

#include <dlfcn.h>
#include <link.h>

#include <string_view>

namespace terrain::view {

#if defined(__SANITIZE_ADDRESS__)
namespace {

int pinDriModule(struct dl_phdr_info* info, std::size_t, void*) {
    const std::string_view path = info->dlpi_name != nullptr ? info->dlpi_name : "";
    if (path.find("/dri/") == std::string_view::npos || !path.ends_with("_dri.so")) return 0;
    // RTLD_NOLOAD: only a module already loaded; RTLD_NODELETE: never unloaded afterwards.
    if (void* handle = dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE)) {
        dlclose(handle);
    }
    return 0;
}

}  // namespace

void keepGlDriverLoadedForLeakChecks() { dl_iterate_phdr(&pinDriModule, nullptr); }
#else
void keepGlDriverLoadedForLeakChecks() {}
#endif

}  // namespace terrain::view
