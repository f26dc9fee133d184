#include "FaultPrinter.h"

#include <fmt/core.h>

#include <cstdio>

namespace terrain::tools {

void FaultPrinter::printNew(const runtime::TileStreamer& streamer) {
    const auto& faults = streamer.faults();
    for (; m_printed < faults.size() && m_printed < m_maxPrinted; ++m_printed)
        fmt::print(stderr, "{}: fault: {}\n", m_tool, faults[m_printed].message);
}

void FaultPrinter::printRest(const runtime::TileStreamer& streamer) {
    printNew(streamer);
    if (streamer.faults().size() > m_printed)
        fmt::print(stderr, "{}: {} more faults not printed\n", m_tool,
                   streamer.faults().size() - m_printed);
}

}  // namespace terrain::tools
