// GlobeGroundHeight: the height of the ground a globe pyramid draws under a latitude and
// longitude, from its finest patch there, read from disk. Tools use it to place a camera a
// given height above the ground (the default flight ends 1 m above the data; the stress
// flight skims it), where the runtime's resident tiles may not yet hold the finest level;
// terrain-bench measures the LOD's own error against it (the pyramid at full detail), apart
// from the finest level's resampling of the sources.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidReader.h"

#include <unordered_map>
#include <utility>

namespace terrain::io {

struct GlobeGround {
    double heightM = 0.0;  ///< above the ellipsoid; 0 where no source reaches
    int faceLevel = -1;    ///< the face level of the patch it came from; −1: no data there
};

/// Asks one pyramid for the ground at many places; keeps the patches it read (a bounded
/// cache), so a camera moving over one patch, or a frame measured pixel by pixel, reads each
/// patch once. Same thread rules as the reader it owns.
class GlobeGroundQuery {
public:
    /// Errors: the pyramid cannot be opened, or is not a globe pyramid.
    static Result<GlobeGroundQuery> open(const std::filesystem::path& pyramid);

    /// The ground of the finest present patch over `latitudeDeg`, `longitudeDeg`: its
    /// samples' heights interpolated over the cell that holds the point, the higher of the
    /// cell's two triangulations (the tessellator picks one), so a camera placed above it is
    /// above the ground whichever is drawn once the patch is refined near it (a coarse
    /// patch's flat triangles sag below the ellipsoid; its finer, virtual children do not).
    /// Where no source reaches, the bare ellipsoid: height 0, faceLevel −1. Errors: a patch
    /// that cannot be read (named by the reader).
    Result<GlobeGround> at(double latitudeDeg, double longitudeDeg);

    /// The finest present patch's heights at the point on each of its cell's two
    /// triangulations (a–d, b–c), as GlobeSourceSurface::heightsAt gives the sources': the
    /// full-detail surface of the pyramid, (0, 0) where no source reaches.
    Result<std::pair<double, double>> heightsAt(double latitudeDeg, double longitudeDeg);

    PyramidReader& reader() { return m_reader; }

private:
    struct CellHeights {
        double alongAD = 0.0, alongBC = 0.0;
        int faceLevel = -1;
    };
    explicit GlobeGroundQuery(PyramidReader reader) : m_reader(std::move(reader)) {}
    Result<CellHeights> cellHeights(double latitudeDeg, double longitudeDeg);
    Result<const PatchRecord*> patch(const PatchId& id);
    Result<PatchInfo> info(const PatchId& id);

    /// Patches kept before the cache starts over: a 1080p frame's finest patches in view.
    static constexpr std::size_t kCachedPatches = 256;

    PyramidReader m_reader;
    std::unordered_map<PatchId, PatchRecord, PatchIdHash> m_patches;
    /// The infos of the patches on the way down (a query walks from a face root), kept
    /// apart from the patches: a camera moving over one face reads each ancestor once.
    static constexpr std::size_t kCachedInfos = 4096;
    std::unordered_map<PatchId, PatchInfo, PatchIdHash> m_infos;
};

}  // namespace terrain::io
