#include "terrain/base/PeakMemory.h"

#include <fstream>
#include <string>
#include <string_view>

namespace terrain {
namespace {

// A "Name:   1234 kB" line of /proc/self/status, in bytes; 0 when absent.
std::uint64_t statusKilobytes(std::string_view key) {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind(key, 0) == 0) return std::stoull(line.substr(key.size())) * 1024;
    }
    return 0;
}

}  // namespace

std::uint64_t peakResidentBytes() { return statusKilobytes("VmHWM:"); }

std::uint64_t currentResidentBytes() { return statusKilobytes("VmRSS:"); }

}  // namespace terrain
