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

// The filled samples of a source with a surface beneath it (VoidFill.h), drawn at the finest
// level that holds them, against that surface. A harmonic fill of the difference stays within
// the largest difference at the rims (the maximum principle), so the drawn fill may depart
// from the surface beneath by that much and the patch's Err(P) (the drawn triangles against
// the composite), no more.
template <typename PatchIdAt, typename PatchAt>
Status checkFilledSamples(const GlobeSources& composite, int faceLevels, const PatchIdAt& patchIdAt,
                          const PatchAt& patchAt, SourceCheckReport& report) {
    for (std::size_t k = 0; k < composite.sources().size(); ++k) {
        const GeographicGrid& grid = composite.sources()[k].grid;
        if (grid.filledOverBeneath() == 0) continue;
        double rim = 0.0;  // the largest difference to the surface beneath at a void's rim
        for (std::int64_t row = 0; row < grid.height(); ++row)
            for (std::int64_t col = 0; col < grid.width(); ++col) {
                if (!grid.validAt(col, row)) continue;
                const bool atRim = (col > 0 && !grid.validAt(col - 1, row)) ||
                                   (col + 1 < grid.width() && !grid.validAt(col + 1, row)) ||
                                   (row > 0 && !grid.validAt(col, row - 1)) ||
                                   (row + 1 < grid.height() && !grid.validAt(col, row + 1));
                if (!atRim) continue;
                const std::optional<double> under =
                    composite.beneath(k, grid.latitudeOf(row), grid.longitudeOf(col));
                if (under) rim = std::max(rim, std::abs(double(grid.heightAt(col, row)) - *under));
            }
        report.largestRimDifferenceM = std::max(report.largestRimDifferenceM, rim);
        for (std::int64_t row = 0; row < grid.height(); ++row)
            for (std::int64_t col = 0; col < grid.width(); ++col) {
                const std::optional<GlobeSources::FilledSample> sample =
                    composite.filledSample(k, col, row);
                if (!sample || !sample->beneath) continue;
                const glm::dvec3 normal =
                    globe::Wgs84::normalAt(sample->latitudeDeg, sample->longitudeDeg);
                const globe::FacePoint p = globe::facePointOf(normal);
                // The finest patch that exists there draws it.
                const LoadedPatch* finest = nullptr;
                for (int level = 0; level < faceLevels; ++level) {
                    Result<LoadedPatch*> found = patchAt(patchIdAt(p, level));
                    if (!found) return found.error();
                    if (!found.value()->present) break;
                    finest = found.value();
                }
                if (finest == nullptr) continue;
                const auto [alongAD, alongBC] = finest->surface->drawnHeights(normal, p);
                const double deviation = std::max(std::abs(alongAD - *sample->beneath),
                                                  std::abs(alongBC - *sample->beneath));
                ++report.filledSamplesChecked;
                report.largestFilledDeviationM =
                    std::max(report.largestFilledDeviationM, deviation);
                const double allowed =
                    rim + double(finest->record.info.error) + SourceCheckReport::kFilledToleranceM;
                if (deviation > allowed) ++report.filledBeyondRimCount;
            }
    }
    return {};
}

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
    Result<GlobeSources> read = GlobeSources::read(
        sources, std::uint64_t{8} << 30, layout.patchQuads(), manifest.globe->oversampleLevels);
    if (!read) return read.error();
    const GlobeSources& composite = read.value();
    const int faceLevels = manifest.globe->faceFinestLevel + 1;
    SourceCheckReport report;
    report.tightestRatio.assign(static_cast<std::size_t>(layout.levelCount()), 0.0);
    std::map<std::tuple<int, std::int64_t, std::int64_t, int>, LoadedPatch> loaded;
    constexpr std::size_t kMaxLoaded = 256;
    const auto patchIdAt = [](const globe::FacePoint& p, int level) {
        const std::int64_t n = globe::patchesPerFaceSide(level);
        return globe::GlobePatchId{
            p.face, level,
            std::clamp<std::int64_t>(static_cast<std::int64_t>(p.s * double(n)), 0, n - 1),
            std::clamp<std::int64_t>(static_cast<std::int64_t>(p.t * double(n)), 0, n - 1)};
    };
    // The patch, read back once while it stays among the kMaxLoaded last ones.
    const auto patchAt = [&](const globe::GlobePatchId& id) -> Result<LoadedPatch*> {
        const auto key = std::tuple(id.face, id.x, id.y, id.level);
        auto it = loaded.find(key);
        if (it != loaded.end()) return &it->second;
        if (loaded.size() >= kMaxLoaded) loaded.clear();
        LoadedPatch patch;
        auto info = reader.patchInfo(layoutPatchOf(id));
        if (!info) return info.error();
        patch.present = info.value().present;
        if (patch.present) {
            if (Status readPatch = reader.readPatch(layoutPatchOf(id), patch.record); !readPatch)
                return readPatch.error();
            patch.surface =
                std::make_unique<GlobePatchSurface>(id, layout.patchQuads(), patch.record.heights);
        }
        return &loaded.emplace(key, std::move(patch)).first->second;
    };
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
                    const globe::GlobePatchId id = patchIdAt(p, level);
                    Result<LoadedPatch*> found = patchAt(id);
                    if (!found) return found.error();
                    const auto it = std::pair{0, found.value()};
                    if (!it.second->present) {
                        if (level == 0)
                            return Error{fmt::format("{}: face {} is missing",
                                                     reader.folder().string(), id.face)};
                        break;  // no finer patch holds it either: the ancestor draws it
                    }
                    const auto [alongAD, alongBC] = it.second->surface->drawnHeights(normal, p);
                    const double distance = std::max(std::abs(alongAD - h), std::abs(alongBC - h));
                    const float bound = it.second->record.info.error;
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
    if (Status filled = checkFilledSamples(composite, faceLevels, patchIdAt, patchAt, report);
        !filled)
        return filled.error();
    return report;
}

}  // namespace terrain::io
