#include "terrain/base/ProcessResources.h"

#include <filesystem>
#include <system_error>

namespace terrain {

namespace {

std::uint64_t entriesOf(const char* folder) {
    std::error_code ec;
    std::uint64_t n = 0;
    for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end;
         it.increment(ec))
        ++n;
    return ec ? 0 : n;
}

}  // namespace

std::uint64_t openFileDescriptors() {
    const std::uint64_t n = entriesOf("/proc/self/fd");
    return n > 0 ? n - 1 : 0;  // the listing's own descriptor
}

std::uint64_t threadCount() { return entriesOf("/proc/self/task"); }

}  // namespace terrain
