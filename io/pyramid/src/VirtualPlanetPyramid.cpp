#include "terrain/pyramid/VirtualPlanetPyramid.h"

#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/GlobePatchErrors.h"
#include "terrain/source/KeyValueSpec.h"
#include "terrain/pyramid/PatchErrors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace terrain::io {

namespace {

struct Summit {
    double latitude = 0.0, longitude = 0.0, height = -std::numeric_limits<double>::infinity();
};

// The highest summit a search finds: the best of a grid 0.8° by 1° between 70° S and 70° N,
// climbed by a pattern search whose step halves down to about 10 m. A view target, not the
// planet's highest point.
Summit findSummit(const ProceduralPlanet& planet) {
    Summit best;
    for (int row = 0; row < 179; ++row) {
        // Away from the poles, so the box around it stays a box.
        const double latitude = -70.0 + 140.0 * row / 178.0;
        for (int col = 0; col < 360; ++col) {
            const double longitude = -179.5 + col;
            const double h = planet.heightAtDegrees(latitude, longitude);
            if (h > best.height) best = {latitude, longitude, h};
        }
    }
    for (double step = 0.5; step > 1e-4; step *= 0.5) {
        for (bool moved = true; moved;) {
            moved = false;
            for (const auto& [dy, dx] :
                 {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}}) {
                const double latitude = std::clamp(best.latitude + dy * step, -75.0, 75.0);
                const double longitude = std::clamp(best.longitude + dx * step, -179.0, 179.0);
                const double h = planet.heightAtDegrees(latitude, longitude);
                if (h > best.height) {
                    best = {latitude, longitude, h};
                    moved = true;
                }
            }
        }
    }
    return best;
}

}  // namespace

bool isVirtualPlanetName(const std::filesystem::path& name) {
    return name.native().starts_with(VirtualPlanetPyramid::kPrefix);
}

Result<VirtualPlanetPyramid> VirtualPlanetPyramid::open(const std::filesystem::path& name) {
    const std::string spec = name.string();
    if (!isVirtualPlanetName(name))
        return Error{
            fmt::format("{}: not the virtual planet (it starts with '{}')", spec, kPrefix)};
    ProceduralPlanetParameters parameters;
    int faceLevel = kDefaultFaceLevel;
    int imagery = 1;
    const Status parsed = parseKeyValueSpec(
        spec, kPrefix, "seed, level, imagery", [&](std::string_view key, std::string_view value) {
            bool ok = true;
            if (key == "seed")
                ok = parseSpecNumber(value, parameters.seed);
            else if (key == "level")
                ok = parseSpecNumber(value, faceLevel) && faceLevel >= 0 &&
                     faceLevel <= kMaxGlobeFaceLevel;
            else if (key == "imagery")
                ok = parseSpecNumber(value, imagery) && (imagery == 0 || imagery == 1);
            else
                return SpecKey::Unknown;
            return ok ? SpecKey::Taken : SpecKey::BadValue;
        });
    if (!parsed) return parsed.error();

    Result<PyramidLayout> layout = globeLayout(faceLevel);
    if (!layout) return Error{fmt::format("{}: {}", spec, layout.error().message)};
    VirtualPlanetPyramid pyramid;
    pyramid.m_planet = ProceduralPlanet::create(parameters);
    PyramidManifest& m = pyramid.m_manifest;
    m = PyramidManifest::forLayout(layout.value());
    m.formatVersion = PyramidManifest::kGlobeFormatVersion;
    const Summit summit = findSummit(pyramid.m_planet);
    m.globe = ManifestGlobe{.faceFinestLevel = faceLevel,
                            .west = summit.longitude - 0.5,
                            .south = summit.latitude - 0.5,
                            .east = summit.longitude + 0.5,
                            .north = summit.latitude + 0.5,
                            .seams = {},
                            .sources = {}};
    m.georeference = Georeference{.originX = -180.0,
                                  .originY = 90.0,
                                  .pixelSizeX = 1.0,
                                  .pixelSizeY = 1.0,
                                  .epsg = Georeference::kWgs84Geographic,
                                  .crsKind = CrsKind::Geographic};
    // Every height is within ± heightBound: the LOD's horizon occluder shrinks by it.
    m.statistics.minHeight = -pyramid.m_planet.heightBound();
    m.statistics.maxHeight = pyramid.m_planet.heightBound();
    for (ManifestLevel& level : m.levels) {
        if (level.level < ManifestGlobe::kLevelOffset) {
            level.presentPatches = 0;
            continue;
        }
        level.maxError = pyramid.levelError(level.level - ManifestGlobe::kLevelOffset);
    }
    m.statistics.rootError = pyramid.levelError(0);
    m.source.inputs = {spec};
    m.source.reader = "planet";
    m.source.sampleType = "float32";
    m.build.tool = "virtual";
    if (imagery == 1) {
        // The planet's colours (PlanetImagery), two face levels finer than its heights: a
        // tile's 248 texels over a patch's 128 quads make about 7.75 texels per finest height
        // quad (2–3 m at face level 12), so close to the ground a pixel still finds a texel
        // no larger than itself. Generated, they cost no storage, and how many tiles a view
        // needs is set by the screen, not by the finest level.
        m.imagery.push_back(ManifestImageryLayer{
            .name = std::string(kImageryLayerName),
            .kind = std::string(ManifestImageryLayer::kPlanetKind),
            .folder = "",
            .input = "",
            .codec = "",
            .coarsestLevel = ManifestGlobe::kLevelOffset,
            .finestLevel = ManifestGlobe::kLevelOffset +
                           std::min(faceLevel + kImageryExtraLevels, kMaxGlobeFaceLevel),
            .opacity = 1.0});
    }
    return pyramid;
}

double VirtualPlanetPyramid::levelError(int faceLevel) const {
    const int quads = m_manifest.layout.patchQuads();
    // A point of a cell is within one sample step along s and one along t of each of the
    // cell's corners: within 2 · maxSampleAngle of them on the unit sphere (chord ≤ angle).
    const double chord = 2.0 * globe::maxSampleAngle(faceLevel, quads);
    const double heights = m_planet.interpolationErrorBound(chord);
    // The flat triangles' sag under the curved surface, for vertices up to the highest
    // height above the ellipsoid (their spacing grows with it).
    const double spacing = globe::maxSampleSpacing(faceLevel, quads) *
                           (1.0 + m_planet.heightBound() / globe::Wgs84::kMinCurvatureRadius);
    const double sag = globe::flatTriangleErrorBound(spacing, -m_planet.heightBound());
    // The heights are stored as floats: half an ulp at the largest height.
    const double rounding = m_planet.heightBound() * 0x1.0p-24;
    return heights + sag + rounding;
}

Status VirtualPlanetPyramid::generateHeights(const PatchId& id, PatchRecord& out) const {
    const PyramidLayout& layout = m_manifest.layout;
    if (!layout.contains(id) || id.level < ManifestGlobe::kLevelOffset)
        return Error{fmt::format("{}: patch {}/{}/{} is not a patch of the planet",
                                 m_manifest.source.inputs.front(), id.level, id.x, id.y)};
    const globe::GlobePatchId patch = globePatchOf(id);
    const int quads = layout.patchQuads();
    const int tile = layout.tileSamples();
    out.id = id;
    out.heights.resize(static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile));
    out.valid.clear();
    for (int j = -1; j <= quads + 1; ++j) {
        for (int i = -1; i <= quads + 1; ++i) {
            const glm::dvec3 n = globe::patchSampleDirection(patch, quads, i, j);
            out.heights[static_cast<std::size_t>((j + 1) * tile + (i + 1))] =
                static_cast<float>(m_planet.heightAt(n.x, n.y, n.z));
        }
    }
    PatchInfo& info = out.info;
    info = PatchInfo{};
    info.present = true;
    summariseDrawnSamples(layout, out.heights, {}, info);
    // The level's bound, computed once when the planet was opened (the manifest's maxError).
    info.approxError =
        roundUpToFloat(m_manifest.levels[static_cast<std::size_t>(id.level)].maxError);
    info.error = info.approxError;
    info.presentChildren = patch.level < m_manifest.globe->faceFinestLevel ? 0xF : 0;
    return {};
}

Status VirtualPlanetPyramid::generate(const PatchId& id, PatchRecord& out) const {
    if (Status generated = generateHeights(id, out); !generated) return generated;
    const PyramidLayout& layout = m_manifest.layout;
    const int tile = layout.tileSamples();
    const GridView interior{out.heights.data() + tile + 1, layout.patchSamples(), tile};
    out.blockErrors.resize(
        static_cast<std::size_t>(layout.blocksPerSide() * layout.blocksPerSide()));
    globePatchBlockErrors(interior, layout.blockQuads(), globePatchOf(id).level, out.info.minHeight,
                          out.blockErrors);
    return {};
}

Result<PatchInfo> VirtualPlanetPyramid::info(const PatchId& id) const {
    PatchRecord record;
    if (Status generated = generateHeights(id, record); !generated) return generated.error();
    return record.info;
}

}  // namespace terrain::io
