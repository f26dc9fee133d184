// VerticalTransform: how a source's raw samples become heights in metres; the manifest records
// it, the readers apply it and the height codes store in its units.
#pragma once

namespace terrain::io {

/// Heights in metres are `raw · scale + offset` (e.g. Puget Sound PNGs: scale 0.1).
struct VerticalTransform {
    double scale = 1.0;
    double offset = 0.0;
    bool operator==(const VerticalTransform&) const = default;
};

}  // namespace terrain::io
