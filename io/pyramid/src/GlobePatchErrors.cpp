#include "terrain/pyramid/GlobePatchErrors.h"

#include "terrain/globe/GlobePatch.h"

#include <cmath>
#include <limits>

namespace terrain::io {

void globePatchBlockErrors(const GridView& interior, int blockQuads, int faceLevel, float minHeight,
                           std::span<BlockErrors> out) {
    patchBlockErrors(interior, blockQuads, out);
    const double spacing = globe::maxSampleSpacing(faceLevel, interior.side - 1);
    for (BlockErrors& block : out) {
        for (std::size_t d = 0; d < block.size(); ++d) {
            const double bulge = globe::flatTriangleErrorBound(spacing * double(2 << d), minHeight);
            const double sum = double(block[d]) + bulge;
            auto rounded = static_cast<float>(sum);
            if (double(rounded) < sum)
                rounded = std::nextafter(rounded, std::numeric_limits<float>::infinity());
            block[d] = rounded;
        }
    }
}

}  // namespace terrain::io
