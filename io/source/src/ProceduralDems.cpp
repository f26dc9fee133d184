// The procedural sources by name, and the readWindow precondition every reader shares.
#include "terrain/source/ProceduralDems.h"

#include "ProceduralReaders.h"
#include "terrain/base/Assert.h"

#include <string_view>

namespace terrain::io {
namespace {
constexpr std::string_view kProceduralPrefix = "procedural:";
constexpr std::string_view kPlanetPrefix = "planet:";
}  // namespace

bool isProceduralDemName(const std::string& input) {
    return input.starts_with(kProceduralPrefix) || input.starts_with(kPlanetPrefix);
}

Result<std::unique_ptr<DemReader>> openProceduralDem(const std::string& name,
                                                     const DemInfoAdjustment& adjust) {
    if (name.starts_with(kPlanetPrefix)) return detail::openProceduralPlanetDem(name, adjust);
    if (name.starts_with(kProceduralPrefix)) return detail::openProceduralTerrainDem(name, adjust);
    return Error{name + ": not a procedural source (procedural:… or planet:…)"};
}

void assertDemWindow(const DemInfo& info, std::int64_t x0, std::int64_t y0, std::int64_t width,
                     std::int64_t rows, std::span<float> out) {
    TERRAIN_ASSERT(x0 >= 0 && y0 >= 0 && width >= 0 && rows >= 0 && x0 + width <= info.width &&
                       y0 + rows <= info.height,
                   "DemReader::readWindow: the window is outside the raster");
    TERRAIN_ASSERT(out.size() >= static_cast<std::size_t>(width * rows),
                   "DemReader::readWindow: out is smaller than the window");
}

}  // namespace terrain::io
