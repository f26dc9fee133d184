// FaultPrinter: a tool's stderr line for each tile that fails to stream, printed once, as it
// happens (the first few; then how many more), so a damaged pyramid is never only a counter
// in the JSON. The runtime itself keeps drawing the failed tile's ancestor.
#pragma once

#include "terrain/runtime/TileStreamer.h"

#include <cstddef>
#include <string>
#include <utility>

namespace terrain::tools {

class FaultPrinter {
public:
    explicit FaultPrinter(std::string tool, std::size_t maxPrinted = 10)
        : m_tool(std::move(tool)), m_maxPrinted(maxPrinted) {}

    /// Prints the faults `streamer` reported since the last call, up to the cap.
    void printNew(const runtime::TileStreamer& streamer);
    /// Prints what printNew has not, then how many faults the cap left out (nothing if
    /// none); call once at the end.
    void printRest(const runtime::TileStreamer& streamer);

private:
    std::string m_tool;
    std::size_t m_maxPrinted;
    std::size_t m_printed = 0;
};

}  // namespace terrain::tools
