#include "BenchTruth.h"

#include "terrain/build/GlobeSourceSurface.h"
#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/GlobeReferenceScene.h"
#include "terrain/runtime/GlobeTruth.h"
#include "terrain/source/DemReader.h"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <utility>

namespace terrain::tools {
namespace {

class PlaneBenchTruth final : public BenchTruth {
public:
    static Result<std::unique_ptr<BenchTruth>> open(const BenchTruthSpec& spec) {
        if (!spec.sources.empty())
            return Error{spec.pyramid +
                         ": a planar pyramid is measured against its finest level (or "
                         "--reference's); --source is for globe pyramids only"};
        auto probe =
            runtime::AccuracyProbe::create(spec.pyramid, spec.probe, spec.referencePyramid);
        if (!probe) return probe.error();
        auto truth = std::make_unique<PlaneBenchTruth>();
        truth->m_probe = std::move(probe).value();
        return std::unique_ptr<BenchTruth>(std::move(truth));
    }
};

// The sources, read as the build read them, and the pyramid's finest level: what the globe's
// truths and reference scene read, so they outlive the probe (declared before it is set).
class GlobeBenchTruth final : public BenchTruth {
public:
    static Result<std::unique_ptr<BenchTruth>> open(const io::PyramidManifest& manifest,
                                                    const BenchTruthSpec& spec);
    ~GlobeBenchTruth() override { m_probe.reset(); }

private:
    std::vector<std::unique_ptr<io::DemReader>> m_readers;
    std::optional<io::GlobeSourceSurface> m_sources;
    std::optional<io::GlobeGroundQuery> m_finest;
    std::optional<io::PyramidReader> m_pyramid;
};

Result<std::unique_ptr<BenchTruth>> GlobeBenchTruth::open(const io::PyramidManifest& manifest,
                                                          const BenchTruthSpec& spec) {
    if (!spec.referencePyramid.empty())
        return Error{spec.pyramid +
                     ": a globe pyramid is measured against the DEMs it was built from "
                     "(--source); --reference is for planar pyramids only"};
    if (spec.sources.empty())
        return Error{spec.pyramid +
                     ": a globe pyramid is measured against the DEMs it was built from: give "
                     "them with --source"};
    auto truth = std::make_unique<GlobeBenchTruth>();
    // Opened as the build opened them. A projected source's reference surface is then the
    // longitude/latitude grid it was resampled onto, not its own samples' triangles.
    io::DemOpenOptions sourceOptions = spec.sourceOptions;
    sourceOptions.geographicGrid = true;
    std::vector<io::DemReader*> readers;
    for (const std::string& source : spec.sources) {
        auto opened = io::openDem({source}, sourceOptions);
        if (!opened) return opened.error();
        readers.push_back(opened.value().get());
        truth->m_readers.push_back(std::move(opened).value());
    }
    // The sources' whole surface in memory: the bench reads them at every measured pixel.
    constexpr std::uint64_t kSourceBudgetBytes = std::uint64_t{8} << 30;
    auto sources =
        io::GlobeSourceSurface::read(readers, kSourceBudgetBytes, manifest.layout.patchQuads());
    if (!sources) return sources.error();
    truth->m_sources.emplace(std::move(sources).value());
    auto finest = io::GlobeGroundQuery::open(spec.pyramid);
    if (!finest) return finest.error();
    truth->m_finest.emplace(std::move(finest).value());
    auto pyramid = io::PyramidReader::open(spec.pyramid);
    if (!pyramid) return pyramid.error();
    truth->m_pyramid.emplace(std::move(pyramid).value());

    std::vector<std::unique_ptr<runtime::TruthSurface>> truths;
    io::GlobeSourceSurface& surface = *truth->m_sources;
    truths.push_back(std::make_unique<runtime::GlobeTruth>(
        [&surface](double latitude, double longitude) -> Result<std::pair<double, double>> {
            return surface.heightsAt(latitude, longitude);
        }));
    // The LOD's own error is measured against the finest face level, which is what it draws
    // at full detail, unless native grids replace it near the ground (docs/globe.md, "Native
    // leaves"): there that level is not drawn, and a figure against it would measure the
    // face grid's resampling. Then the sources alone are the truth.
    const bool native =
        std::any_of(manifest.globe->sources.begin(), manifest.globe->sources.end(),
                    [](const io::ManifestGlobeSource& s) { return !s.native.empty(); });
    io::GlobeGroundQuery& query = *truth->m_finest;
    if (!native)
        truths.push_back(
            std::make_unique<runtime::GlobeTruth>([&query](double latitude, double longitude) {
                return query.heightsAt(latitude, longitude);
            }));
    auto probe = runtime::AccuracyProbe::create(
        std::make_unique<runtime::GlobeReferenceScene>(*truth->m_pyramid), std::move(truths),
        spec.probe);
    if (!probe) return probe.error();
    truth->m_probe = std::move(probe).value();
    return std::unique_ptr<BenchTruth>(std::move(truth));
}

}  // namespace

Result<std::unique_ptr<BenchTruth>> BenchTruth::open(const io::PyramidManifest& manifest,
                                                     const BenchTruthSpec& spec) {
    if (manifest.globe) return GlobeBenchTruth::open(manifest, spec);
    return PlaneBenchTruth::open(spec);
}

}  // namespace terrain::tools
