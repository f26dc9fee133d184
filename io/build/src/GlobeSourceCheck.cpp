// terrain-inspect --verify --source on a globe pyramid: every source sample the composite
// shows (GlobeSources::measuredSample: a projected source's own samples, each placed through
// its CRS, not the grid it was resampled onto), at every face level whose patch holding it exists,
// against that patch's drawn triangles along the sample's normal (GlobePatchSurface, both
// diagonals). Independent of the builder's bookkeeping: it reads the source files again and every
// patch back from the shards. A sample whose patch of some level does not exist (a coarse source
// past its finest level) is drawn there by the ancestor, whose level checks it.
#include "GlobeSourceCheck.h"

#include "GlobeSources.h"
#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/build/GlobePatchSurface.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <tuple>

namespace terrain::io {

namespace {

struct LoadedPatch {
    bool present = false;
    PatchRecord record;
    std::unique_ptr<GlobePatchSurface> surface;
};

}  // namespace

Result<SourceCheckReport> checkGlobeErrorBoundsAgainstSources(
    PyramidReader& reader, std::span<DemReader* const> sources,
    const std::function<void(double fraction)>& progress) {
    const PyramidManifest& manifest = reader.manifest();
    const PyramidLayout& layout = reader.layout();
    for (DemReader* source : sources)
        if (source->info().georeference.crsKind != CrsKind::Geographic)
            return Error{
                fmt::format("{}: not a geographic source; the globe pyramid {} was built "
                            "from geographic ones, or projected ones with a known CRS",
                            source->info().path, reader.folder().string())};
    Result<GlobeSources> read =
        GlobeSources::read(sources, std::uint64_t{8} << 30, layout.patchQuads());
    if (!read) return read.error();
    const GlobeSources& composite = read.value();
    const int faceLevels = manifest.globe->faceFinestLevel + 1;
    SourceCheckReport report;
    report.tightestRatio.assign(static_cast<std::size_t>(layout.levelCount()), 0.0);
    std::map<std::tuple<int, std::int64_t, std::int64_t, int>, LoadedPatch> loaded;
    constexpr std::size_t kMaxLoaded = 256;
    std::int64_t rowsDone = 0, rowsTotal = 0;
    for (std::size_t k = 0; k < composite.sources().size(); ++k)
        rowsTotal += composite.measuredHeight(k);
    for (std::size_t k = 0; k < composite.sources().size(); ++k) {
        const std::int64_t width = composite.measuredWidth(k);
        for (std::int64_t row = 0; row < composite.measuredHeight(k); ++row) {
            for (std::int64_t col = 0; col < width; ++col) {
                const std::optional<GlobeSources::MeasuredSample> sample =
                    composite.measuredSample(k, col, row);
                if (!sample) continue;
                const double h = sample->height;
                const glm::dvec3 normal =
                    globe::Wgs84::normalAt(sample->latitudeDeg, sample->longitudeDeg);
                const globe::FacePoint p = globe::facePointOf(normal);
                for (int level = 0; level < faceLevels; ++level) {
                    const std::int64_t n = globe::patchesPerFaceSide(level);
                    const globe::GlobePatchId id{
                        p.face, level,
                        std::clamp<std::int64_t>(static_cast<std::int64_t>(p.s * double(n)), 0,
                                                 n - 1),
                        std::clamp<std::int64_t>(static_cast<std::int64_t>(p.t * double(n)), 0,
                                                 n - 1)};
                    const auto key = std::tuple(id.face, id.x, id.y, level);
                    auto it = loaded.find(key);
                    if (it == loaded.end()) {
                        if (loaded.size() >= kMaxLoaded) loaded.clear();
                        LoadedPatch patch;
                        auto info = reader.patchInfo(layoutPatchOf(id));
                        if (!info) return info.error();
                        patch.present = info.value().present;
                        if (patch.present) {
                            if (Status readPatch =
                                    reader.readPatch(layoutPatchOf(id), patch.record);
                                !readPatch)
                                return readPatch.error();
                            patch.surface = std::make_unique<GlobePatchSurface>(
                                id, layout.patchQuads(), patch.record.heights);
                        }
                        it = loaded.emplace(key, std::move(patch)).first;
                    }
                    if (!it->second.present) {
                        if (level == 0)
                            return Error{fmt::format("{}: face {} is missing",
                                                     reader.folder().string(), id.face)};
                        break;  // no finer patch holds it either: the ancestor draws it
                    }
                    const auto [alongAD, alongBC] = it->second.surface->drawnHeights(normal);
                    const double distance = std::max(std::abs(alongAD - h), std::abs(alongBC - h));
                    const float bound = it->second.record.info.error;
                    const int layoutLevel = level + ManifestGlobe::kLevelOffset;
                    ++report.samplesChecked;
                    double& tightest = report.tightestRatio[static_cast<std::size_t>(layoutLevel)];
                    if (bound > 0.0f) tightest = std::max(tightest, distance / double(bound));
                    if (distance > double(bound)) {
                        ++report.violationCount;
                        if (report.violations.size() < SourceCheckReport::kMaxListed)
                            report.violations.push_back(
                                {layoutPatchOf(id), col, row, distance, bound});
                    }
                }
            }
            if (progress && ++rowsDone % 64 == 0) progress(double(rowsDone) / double(rowsTotal));
        }
    }
    return report;
}

}  // namespace terrain::io
