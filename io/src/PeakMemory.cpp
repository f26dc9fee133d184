#include "terrain/io/PeakMemory.h"

#include <fstream>
#include <string>

namespace terrain::io {

std::uint64_t peakResidentBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;  // kB
    }
    return 0;
}

}  // namespace terrain::io
