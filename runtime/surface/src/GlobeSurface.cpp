// GlobeSurface: the cube faces' quadtrees in the layout, oriented boxes, the ellipsoid's
// curvature, the horizon.
#include "terrain/runtime/GlobeSurface.h"

#include "terrain/base/Assert.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/runtime/GlobeFrustum.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace terrain::runtime {
namespace {

// A patch's share of GlobeSurface::coverageOf: face level l counts 4^(30 − l).
constexpr int kCoverageLevels = 30;

// A source's extent as a box whose west ≤ east (across the antimeridian east runs past 180°).
GlobeSurface::LonLatBox extentOf(const io::ManifestGlobeSource& source) {
    return {source.west, source.east < source.west ? source.east + 360.0 : source.east,
            source.south, source.north};
}

bool meets(const GlobeSurface::LonLatBox& a, const GlobeSurface::LonLatBox& b) {
    if (a.south >= b.north || a.north <= b.south) return false;
    for (const double turn : {-360.0, 0.0, 360.0})
        if (a.west + turn < b.east && a.east + turn > b.west) return true;
    return false;
}

bool within(const GlobeSurface::LonLatBox& a, const GlobeSurface::LonLatBox& b) {
    if (a.south < b.south || a.north > b.north) return false;
    for (const double turn : {-360.0, 0.0, 360.0})
        if (a.west + turn >= b.west && a.east + turn <= b.east) return true;
    return false;
}

}  // namespace

// Which ground shows grid `grid`'s source alone (docs/globe.md, "Native windows"). The
// composite there is that source's samples (its voids filled sample by sample) on their own
// triangles. Within the band where it blends into a coarser source the composite mixes the
// two sources' triangles, and within a finer source's extent (its band and edge taper lie
// inside it) the finer source shows; a sample of margin each way takes in every cell that
// touches the ground asked about.
void GlobeSurface::setPurity(NativeGrid& grid, const io::ManifestGlobe& globe) {
    const auto k = static_cast<std::size_t>(grid.source);
    if (k >= globe.sources.size()) return;  // sources not recorded: nothing is known pure
    const io::ManifestGlobeSource& own = globe.sources[k];
    // Only a source over a coarser one is blended into it, in a band along its edges (its
    // seam; the widest taken if two sources share a name).
    double band = 0.0;
    if (k + 1 < globe.sources.size()) {
        bool recorded = false;
        for (const io::ManifestSeam& seam : globe.seams)
            if (seam.input == own.input) {
                band = std::max(band, seam.bandPixels[1]);
                recorded = true;
            }
        // No seams recorded at all (an older manifest): its band is unknown.
        if (!recorded && globe.seams.empty()) return;
    }
    band += 1.0;
    const double lon = grid.geometry.pixelLonDeg, lat = grid.geometry.pixelLatDeg;
    LonLatBox inside = extentOf(own);
    if (inside.east - inside.west >= 360.0) {
        inside.west = -1e9;  // every longitude
        inside.east = 1e9;
    } else {
        inside.west += band * lon;
        inside.east -= band * lon;
    }
    inside.south += band * lat;
    inside.north -= band * lat;
    grid.inside = inside;
    for (std::size_t f = 0; f < k; ++f) {
        LonLatBox finer = extentOf(globe.sources[f]);
        finer.west -= lon;
        finer.east += lon;
        finer.south -= lat;
        finer.north += lat;
        grid.finer.push_back(finer);
    }
}

bool GlobeSurface::isPure(const NativeGrid& grid, const LonLatBox& box) {
    if (!grid.inside || !within(box, *grid.inside)) return false;
    return std::none_of(grid.finer.begin(), grid.finer.end(),
                        [&](const LonLatBox& finer) { return meets(box, finer); });
}

GlobeSurface::GlobeSurface(const io::PyramidManifest& manifest,
                           std::span<const io::NativeGridManifest> nativeGrids)
    : Surface(manifest), m_occluderShrinkM(std::max(0.0, -manifest.statistics.minHeight) + 1.0) {
    TERRAIN_ASSERT(manifest.globe.has_value(), "GlobeSurface needs a globe pyramid");
    TERRAIN_ASSERT(manifest.globe->faceFinestLevel <= io::kMaxGlobeFaceLevel,
                   "readManifest refuses deeper globe pyramids");
    for (int face = 0; face < globe::kCubeFaces; ++face)
        m_roots[static_cast<std::size_t>(face)] = io::layoutPatchOf({face, 0, 0, 0});
    for (const io::NativeGridManifest& native : nativeGrids) {
        const io::Georeference& g = native.manifest.georeference;
        const io::PyramidLayout& tiles = native.manifest.layout;
        NativeGrid grid;
        grid.source = native.source;
        grid.geometry = {g.originX, g.originY, g.pixelSizeX, g.pixelSizeY, tiles.patchQuads()};
        grid.tilesX = tiles.patchesX(tiles.finestLevel());
        grid.tilesY = tiles.patchesY(tiles.finestLevel());
        grid.lastColumn = tiles.rasterWidth() - 1;
        grid.lastRow = tiles.rasterHeight() - 1;
        grid.firstLon = g.originX + 0.5 * g.pixelSizeX;
        grid.lastLon = g.originX + (double(tiles.rasterWidth()) - 0.5) * g.pixelSizeX;
        grid.northLat = g.originY - 0.5 * g.pixelSizeY;
        grid.southLat = g.originY - (double(tiles.rasterHeight()) - 0.5) * g.pixelSizeY;
        // Along a meridian, and along the parallel nearest the equator.
        const double nearestEquator =
            grid.southLat > 0.0 ? grid.southLat : (grid.northLat < 0.0 ? -grid.northLat : 0.0);
        const double radian = std::numbers::pi / 180.0;
        grid.spacingM = globe::Wgs84::kMaxCurvatureRadius * radian *
                        std::max(g.pixelSizeY, g.pixelSizeX * std::cos(nearestEquator * radian));
        setPurity(grid, *manifest.globe);
        m_natives.push_back(grid);
    }
}

const GlobeSurface::NativeGrid* GlobeSurface::nativeGridOf(const io::PatchId& tile) const {
    if (!io::isNativeTile(tile)) return nullptr;
    for (const NativeGrid& grid : m_natives)
        if (grid.source == io::nativeGridOf(tile)) return &grid;
    return nullptr;
}

bool GlobeSurface::nativeTilesOver(const io::PatchId& id, std::vector<io::PatchId>& out) const {
    LonLatBox footprint;
    return nativeGridOver(id, out, footprint) != nullptr;
}

bool GlobeSurface::nativeGroundIsPure(const io::PatchId& id) const {
    std::vector<io::PatchId> tiles;
    LonLatBox footprint;
    const NativeGrid* grid = nativeGridOver(id, tiles, footprint);
    return grid != nullptr && isPure(*grid, footprint);
}

std::optional<glm::dvec4> GlobeSurface::nativeFootprintOn(const io::PatchId& id,
                                                          const io::PatchId& tile) const {
    std::vector<io::PatchId> tiles;
    LonLatBox footprint;
    const NativeGrid* grid = nativeGridOver(id, tiles, footprint);
    if (grid == nullptr || std::find(tiles.begin(), tiles.end(), tile) == tiles.end())
        return std::nullopt;
    // Tile coordinates: sample i of tile x at u = i / quads, sample i at column x·quads + i.
    const double q = grid->geometry.quads;
    const double u0 = grid->columnAt(footprint.west) / q - double(tile.x);
    const double u1 = grid->columnAt(footprint.east) / q - double(tile.x);
    const double v0 = grid->rowAt(footprint.north) / q - double(tile.y);
    const double v1 = grid->rowAt(footprint.south) / q - double(tile.y);
    return glm::dvec4(u0, v0, u1, v1);
}

bool GlobeSurface::nativeWindowIsPure(const io::PatchId& tile,
                                      const globe::NativeWindow& window) const {
    const NativeGrid* grid = nativeGridOf(tile);
    if (grid == nullptr) return false;
    const globe::NativeGridGeometry& geo = grid->geometry;
    // The window's samples, and a sample round them: the cells its ground takes in.
    const glm::dvec2 northWest = geo.lonLatDeg(tile.x, tile.y, window.u0(), window.v0());
    const glm::dvec2 southEast =
        geo.lonLatDeg(tile.x, tile.y, window.u0() + window.size(), window.v0() + window.size());
    const LonLatBox box{northWest.x - geo.pixelLonDeg, southEast.x + geo.pixelLonDeg,
                        southEast.y - geo.pixelLatDeg, northWest.y + geo.pixelLatDeg};
    return isPure(*grid, box);
}

const GlobeSurface::NativeGrid* GlobeSurface::nativeGridOver(const io::PatchId& id,
                                                             std::vector<io::PatchId>& out,
                                                             LonLatBox& footprint) const {
    if (m_natives.empty()) return nullptr;
    // Most patches asked are far coarser than every grid: no footprint to work out for them.
    const double spacing = sampleSpacingM(id.level);
    if (std::none_of(m_natives.begin(), m_natives.end(), [&](const NativeGrid& grid) {
            return grid.spacingM <= kMaxNativeSpacingRatio * spacing;
        }))
        return nullptr;
    const globe::GlobePatchId g = io::globePatchOf(id);
    // A patch round a pole has none: the pole is one point of every longitude's grid.
    const double side = double(globe::patchesPerFaceSide(g.level));
    for (const double z : {1.0, -1.0}) {
        const globe::FacePoint pole = globe::facePointOf({0.0, 0.0, z});
        const double u = pole.s * side - double(g.x), v = pole.t * side - double(g.y);
        if (pole.face == g.face && u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0) return nullptr;
    }
    // The footprint's longitudes and latitudes along its edges, unwrapped about the first.
    constexpr int kPerEdge = 16;
    double west = 0.0, east = 0.0, south = 0.0, north = 0.0, first = 0.0;
    for (int k = 0; k < 4 * kPerEdge; ++k) {
        const double t = double(k % kPerEdge) / kPerEdge;
        const int edge = k / kPerEdge;
        const double u = edge == 0 ? t : edge == 1 ? 1.0 : edge == 2 ? 1.0 - t : 0.0;
        const double v = edge == 0 ? 0.0 : edge == 1 ? t : edge == 2 ? 1.0 : 1.0 - t;
        const globe::FacePoint p = globe::patchPoint(g, u, v);
        const globe::Geodetic place =
            globe::Wgs84::geodeticOfNormal(globe::directionOf(p.face, p.s, p.t));
        double longitude = place.longitudeDeg;
        if (k == 0) first = longitude;
        longitude += 360.0 * std::round((first - longitude) / 360.0);
        west = k == 0 ? longitude : std::min(west, longitude);
        east = k == 0 ? longitude : std::max(east, longitude);
        south = k == 0 ? place.latitudeDeg : std::min(south, place.latitudeDeg);
        north = k == 0 ? place.latitudeDeg : std::max(north, place.latitudeDeg);
    }
    // The edges bow between the places sampled: a margin of a sixteenth of the span.
    const double padLon = (east - west) / kPerEdge, padLat = (north - south) / kPerEdge;
    west -= padLon;
    east += padLon;
    south -= padLat;
    north += padLat;
    for (const NativeGrid& grid : m_natives) {
        // A grid much coarser than the patch (a global one under a regional source's patches)
        // would draw tiles that dwarf it, over everything around.
        if (grid.spacingM > kMaxNativeSpacingRatio * spacing) continue;
        const double shift = grid.turnsToward(0.5 * (west + east));
        const double lo = west + shift, hi = east + shift;
        if (!grid.holds(lo, hi, south, north)) continue;
        const globe::NativeGridGeometry& geo = grid.geometry;
        const double q = geo.quads;
        // Tile t holds samples t·q … t·q + q: the tiles holding samples c0 … c1.
        const auto range = [&](double c0, double c1, std::int64_t count) {
            const auto low = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(c0 / q)),
                                                      0, count - 1);
            const auto high = std::clamp<std::int64_t>(
                static_cast<std::int64_t>(std::ceil(c1 / q)) - 1, low, count - 1);
            return std::pair(low, high);
        };
        const auto [x0, x1] = range(grid.columnAt(lo), grid.columnAt(hi), grid.tilesX);
        const auto [y0, y1] = range(grid.rowAt(north), grid.rowAt(south), grid.tilesY);
        if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxNativeTilesPerPatch) continue;
        // A tile the planar pyramid padded past its raster (a grid that ends at a pole) would
        // draw samples beyond it.
        if ((x1 + 1) * geo.quads > grid.lastColumn || (y1 + 1) * geo.quads > grid.lastRow) continue;
        for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t x = x0; x <= x1; ++x)
                out.push_back(io::nativeTileId(grid.source, x, y));
        // With a sample round it: the cells its ground takes in.
        footprint = {lo - geo.pixelLonDeg, hi + geo.pixelLonDeg, south - geo.pixelLatDeg,
                     north + geo.pixelLatDeg};
        return &grid;
    }
    return nullptr;
}

double GlobeSurface::NativeGrid::turnsToward(double longitudeDeg) const {
    return 360.0 * std::round((0.5 * (firstLon + lastLon) - longitudeDeg) / 360.0);
}

std::optional<Surface::NativeTilePoint> GlobeSurface::nativeTileUnder(const glm::dvec3& up,
                                                                      int level) const {
    if (m_natives.empty()) return std::nullopt;
    const globe::Geodetic place = globe::Wgs84::geodeticOfNormal(up);
    const double spacing = sampleSpacingM(level);
    for (const NativeGrid& grid : m_natives) {
        if (grid.spacingM > kMaxNativeSpacingRatio * spacing) continue;
        const double longitude = place.longitudeDeg + grid.turnsToward(place.longitudeDeg);
        if (!grid.holds(longitude, longitude, place.latitudeDeg, place.latitudeDeg)) continue;
        const double q = grid.geometry.quads;
        const double column = grid.columnAt(longitude), row = grid.rowAt(place.latitudeDeg);
        const auto x = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(column / q)),
                                                0, grid.tilesX - 1);
        const auto y = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(row / q)), 0,
                                                grid.tilesY - 1);
        return NativeTilePoint{io::nativeTileId(grid.source, x, y), column / q - double(x),
                               row / q - double(y)};
    }
    return std::nullopt;
}

PatchVolume GlobeSurface::nativeTileVolume(const io::PatchId& tile, float minHeight,
                                           float maxHeight,
                                           const globe::NativeWindow& window) const {
    const NativeGrid* grid = nativeGridOf(tile);
    TERRAIN_ASSERT(grid != nullptr, "a native tile of no native grid");
    return globe::nativeTileBounds(grid->geometry, tile.x, tile.y, minHeight, maxHeight, window);
}

Surface::NativeGeometricErrors GlobeSurface::nativeGeometricErrors(
    const io::PatchId& tile, const io::PatchInfo& info, const io::SampleRises& rises,
    const globe::NativeWindow& window) const {
    const NativeGrid* grid = nativeGridOf(tile);
    if (grid == nullptr) return {};
    const globe::NativeGridGeometry& geo = grid->geometry;
    const double radian = std::numbers::pi / 180.0;
    // The window's rows, a sample round them included (sample row r lies at northDeg −
    // (r + ½)·Δφ): the tile's with its aprons at depth 0.
    const double firstRow = (double(tile.y) + window.v0()) * geo.quads - 1.0;
    const double lastRow = firstRow + window.size() * geo.quads + 2.0;
    const auto latitude = [&](double row) {
        return std::clamp(geo.northDeg - (row + 0.5) * geo.pixelLatDeg, -90.0, 90.0) * radian;
    };
    globe::GeographicCells cells;
    cells.southRad = latitude(lastRow);
    cells.northRad = latitude(firstRow);
    cells.minHeightM = info.minHeight;
    cells.maxHeightM = info.maxHeight;
    const auto boundAt = [&](double span) {
        // Simplified by 2^d, a drawn triangle spans 2^d of the window's cells a side, each
        // 2^-depth of the tile's; its slopes are no steeper than the steepest cell's.
        const double scale = span * window.size();
        cells.lonStepRad = geo.pixelLonDeg * radian * scale;
        cells.latStepRad = geo.pixelLatDeg * radian * scale;
        cells.riseEastM = double(rises.east) * scale;
        cells.riseNorthM = double(rises.north) * scale;
        return globe::geographicTriangleErrorBound(cells);
    };
    NativeGeometricErrors errors;
    errors.fullM = boundAt(1.0);
    for (int d = 0; d < 4; ++d)
        errors.blocksM[static_cast<std::size_t>(d)] = io::roundUpToFloat(boundAt(double(2 << d)));
    return errors;
}

const globe::NativeGridGeometry* GlobeSurface::nativeGeometry(const io::PatchId& tile) const {
    const NativeGrid* grid = nativeGridOf(tile);
    return grid != nullptr ? &grid->geometry : nullptr;
}

int GlobeSurface::maxLevel() const {
    return std::min(kMaxBareFaceLevel, io::kMaxGlobeFaceLevel) + io::ManifestGlobe::kLevelOffset;
}

int GlobeSurface::children(const io::PatchId& id, std::array<SurfaceChild, 4>& out) const {
    const globe::GlobePatchId g = io::globePatchOf(id);
    for (int c = 0; c < 4; ++c) {
        const globe::GlobePatchId child{g.face, g.level + 1, 2 * g.x + (c & 1), 2 * g.y + (c >> 1)};
        out[static_cast<std::size_t>(c)] = {io::layoutPatchOf(child), c};
    }
    return 4;
}

double GlobeSurface::flatTriangleError(int level, const io::SampleRises& rises) const {
    return globe::faceTriangleErrorBound(sampleAngle(level), rises.east, rises.north);
}

std::array<float, 4> GlobeSurface::flatTriangleBlockErrors(int level,
                                                           const io::SampleRises& rises) const {
    std::array<float, 4> errors{};
    for (int d = 0; d < 4; ++d) {
        // Simplified by 2^d, a drawn triangle spans 2^d cells a side, no steeper than one.
        const double scale = double(2 << d);
        errors[static_cast<std::size_t>(d)] = io::roundUpToFloat(globe::faceTriangleErrorBound(
            sampleAngle(level) * scale, double(rises.east) * scale, double(rises.north) * scale));
    }
    return errors;
}

double GlobeSurface::sampleAngle(int level) const {
    return globe::maxSampleAngle(level - io::ManifestGlobe::kLevelOffset, layout().patchQuads());
}

double GlobeSurface::sampleSpacingM(int level) const {
    return globe::maxSampleSpacing(level - io::ManifestGlobe::kLevelOffset, layout().patchQuads());
}

PatchVolume GlobeSurface::volume(const io::PatchId& id, float minHeight, float maxHeight) const {
    return globe::patchBounds(io::globePatchOf(id), minHeight, maxHeight);
}

double GlobeSurface::distance(const glm::dvec3& point, const PatchVolume& volume) const {
    return globe::distanceToBox(point, std::get<globe::OrientedBox>(volume));
}

SurfaceView GlobeSurface::view(const Camera& camera) const {
    SurfaceView view = Surface::view(camera);
    view.horizon.emplace(m_occluderShrinkM);
    view.horizon->setCamera(camera.position);
    return view;
}

bool GlobeSurface::outsideFrustum(const SurfaceView& view, const PatchVolume& volume,
                                  int& /*planeMask*/) const {
    return !frustumMeetsBox(view.frustum, std::get<globe::OrientedBox>(volume));
}

std::uint64_t GlobeSurface::coverageOf(const io::PatchId& id) const {
    const int faceLevel = id.level - io::ManifestGlobe::kLevelOffset;
    return std::uint64_t{1} << (2 * (kCoverageLevels - faceLevel));
}

std::uint64_t GlobeSurface::wholeCoverage() const {
    return std::uint64_t{6} << (2 * kCoverageLevels);
}

}  // namespace terrain::runtime
