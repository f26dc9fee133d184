#include "terrain/runtime/NativeOwnership.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/GlobeLayout.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace terrain::runtime {
namespace {

constexpr int kWindowCells = 8;

}  // namespace

void assignNativeOwnership(PatchDraw& draw, std::span<const io::PatchId> holders) {
    TERRAIN_ASSERT(!holders.empty(), "a native tile drawn for no face patch");
    // The finest, the first in row order among those: the same whatever order they come in.
    const auto finest = std::max_element(
        holders.begin(), holders.end(), [](const io::PatchId& a, const io::PatchId& b) {
            return std::tuple(a.level, -a.y, -a.x) < std::tuple(b.level, -b.y, -b.x);
        });
    draw.imageryPatch = *finest;
    draw.nativeCells = 0;
    draw.nativeWindow = {0, 0};
    const globe::GlobePatchId reference = io::globePatchOf(*finest);
    std::int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    for (std::size_t i = 0; i < holders.size(); ++i) {
        const globe::GlobePatchId h = io::globePatchOf(holders[i]);
        if (h.face != reference.face) return;  // no one grid of cells for both faces
        const int shift = reference.level - h.level;
        const std::int64_t hx0 = std::int64_t(h.x) << shift, hy0 = std::int64_t(h.y) << shift;
        const std::int64_t hx1 = hx0 + (std::int64_t(1) << shift) - 1;
        const std::int64_t hy1 = hy0 + (std::int64_t(1) << shift) - 1;
        x0 = i == 0 ? hx0 : std::min(x0, hx0);
        y0 = i == 0 ? hy0 : std::min(y0, hy0);
        x1 = i == 0 ? hx1 : std::max(x1, hx1);
        y1 = i == 0 ? hy1 : std::max(y1, hy1);
    }
    if (x1 - x0 >= kWindowCells || y1 - y0 >= kWindowCells) return;
    std::uint64_t cells = 0;
    for (const io::PatchId& id : holders) {
        const globe::GlobePatchId h = io::globePatchOf(id);
        const int shift = reference.level - h.level;
        const std::int64_t side = std::int64_t(1) << shift;
        for (std::int64_t y = 0; y < side; ++y)
            for (std::int64_t x = 0; x < side; ++x) {
                const std::int64_t i = (std::int64_t(h.x) << shift) + x - x0;
                const std::int64_t j = (std::int64_t(h.y) << shift) + y - y0;
                cells |= std::uint64_t(1) << (kWindowCells * j + i);
            }
    }
    draw.nativeCells = cells;
    draw.nativeWindow = {static_cast<std::int32_t>(x0 - std::int64_t(reference.x)),
                         static_cast<std::int32_t>(y0 - std::int64_t(reference.y))};
}

bool nativeTileOwns(const PatchDraw& draw, double u, double v) {
    if (draw.nativeCells == 0) return true;
    const double i = std::floor(u) - draw.nativeWindow[0];
    const double j = std::floor(v) - draw.nativeWindow[1];
    if (i < 0.0 || j < 0.0 || i >= kWindowCells || j >= kWindowCells) return false;
    return (draw.nativeCells >> (kWindowCells * int(j) + int(i)) & 1u) != 0;
}

}  // namespace terrain::runtime
