#include "RowFill.h"

#include "terrain/base/Assert.h"
#include "terrain/pyramid/HeightCodes.h"

#include <cmath>

namespace terrain::io::detail {

Result<std::int64_t> RowFill::fill(std::int64_t r, std::int64_t a, std::span<float> row,
                                   std::span<std::uint8_t> valid) {
    TERRAIN_ASSERT(row.size() == valid.size());
    const std::int64_t missing = markValidSamples(row, valid);
    if (missing == 0) return std::int64_t{0};
    Result<const VoidFill*> voids = m_voids.get();
    if (!voids) return voids.error();
    for (std::size_t i = 0; i < row.size(); ++i) {
        if (valid[i]) continue;
        const float h = voids.value()->at(a + static_cast<std::int64_t>(i), r);
        row[i] = m_units ? roundToSourceUnits(h, *m_units) : h;
    }
    return missing;
}

}  // namespace terrain::io::detail
