// VirtualPlanetPyramid: the built-in procedural planet (ProceduralPlanet) as a globe pyramid
// whose patches are generated when they are read, not stored (issue 20: stream a whole
// planet at full resolution without terabytes). It is named in place of a pyramid folder:
//
//     planet:                    seed 1, face levels 0 … 12 (samples 17–25 m apart)
//     planet:seed=7,level=14     keys: seed, level (0 … kMaxGlobeFaceLevel),
//     planet:imagery=0           imagery (1: the default; 0: no imagery layer)
//
// readManifest and PyramidReader::open accept the name, so the I/O thread, the streamer,
// the ground queries and every tool that opens a pyramid open the planet too. A patch is the
// planet's heights at its samples' ellipsoid normals (bit-identical on shared edges, as the
// directions are), its λ(d) as a built globe patch's (globePatchBlockErrors), and its Err(P)
// from the planet's closed-form bound (ProceduralPlanet::interpolationErrorBound) over a cell
// of its level plus the ellipsoid's bulge: a bound against the planet's continuous surface,
// which is finer than any level, so it holds against every finer level too. Every patch of
// every face level is present. "Go to the data" (the manifest's extent) is a 1° box around
// the highest summit a search of the planet finds. Its manifest lists one imagery layer,
// "planet-colours" (kind "planet": PlanetImagery, generated as the heights are), from the
// faces' root down to two face levels below the heights' finest, unless imagery=0.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/source/ProceduralPlanet.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <filesystem>
#include <string_view>

namespace terrain::io {

/// True when `name` names the virtual planet ("planet:…") rather than a folder.
bool isVirtualPlanetName(const std::filesystem::path& name);

class VirtualPlanetPyramid {
public:
    static constexpr std::string_view kPrefix = "planet:";
    static constexpr int kDefaultFaceLevel = 12;
    static constexpr std::string_view kImageryLayerName = "planet-colours";
    /// Face levels of imagery below the heights' finest (up to kMaxGlobeFaceLevel).
    static constexpr int kImageryExtraLevels = 2;

    /// Parses the name; errors name it and the bad key.
    static Result<VirtualPlanetPyramid> open(const std::filesystem::path& name);

    const PyramidManifest& manifest() const { return m_manifest; }
    const ProceduralPlanet& planet() const { return m_planet; }

    /// Generates the patch (any thread: const, no shared state). Errors: outside the pyramid
    /// or above the faces, naming the patch.
    Status generate(const PatchId& id, PatchRecord& out) const;
    /// The same patch's info alone (its heights computed, not its λ(d)).
    Result<PatchInfo> info(const PatchId& id) const;

    /// Err(P) of every patch of a face level, metres (generate() stores it in each patch).
    double levelError(int faceLevel) const;

private:
    Status generateHeights(const PatchId& id, PatchRecord& out) const;

    PyramidManifest m_manifest;
    ProceduralPlanet m_planet;
};

}  // namespace terrain::io
