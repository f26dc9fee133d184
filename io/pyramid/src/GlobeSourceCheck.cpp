// terrain-inspect --verify --source on a globe pyramid: every valid source sample, at every
// face level, against the drawn triangles of the patch that holds its normal
// (GlobePatchSurface, both diagonals). Independent of the builder's bookkeeping: it streams
// the source file again and reads every patch back from the shards.
#include "GlobeSourceCheck.h"

#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/io/GlobeLayout.h"
#include "terrain/io/GlobePatchSurface.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <tuple>

namespace terrain::io {

namespace {

struct LoadedPatch {
    PatchRecord record;
    std::unique_ptr<GlobePatchSurface> surface;
};

}  // namespace

Result<SourceCheckReport> checkGlobeErrorBoundsAgainstSource(
    PyramidReader& reader, DemReader& source,
    const std::function<void(double fraction)>& progress) {
    const PyramidManifest& manifest = reader.manifest();
    const PyramidLayout& layout = reader.layout();
    const DemInfo& dem = source.info();
    const Georeference& g = dem.georeference;
    if (g.crsKind != CrsKind::Geographic || dem.width <= 0 || dem.height <= 0)
        return Error{
            fmt::format("{}: not a geographic source; the globe pyramid {} was built "
                        "from one",
                        dem.path, reader.folder().string())};
    const int faceLevels = manifest.globe->faceFinestLevel + 1;
    SourceCheckReport report;
    report.tightestRatio.assign(static_cast<std::size_t>(layout.levelCount()), 0.0);
    std::map<std::tuple<int, std::int64_t, std::int64_t, int>, LoadedPatch> loaded;
    constexpr std::size_t kMaxLoaded = 256;
    constexpr std::int64_t kRowsPerRead = 16;
    std::vector<float> samples;
    for (std::int64_t y = 0; y < dem.height; y += kRowsPerRead) {
        const std::int64_t rows = std::min(kRowsPerRead, dem.height - y);
        samples.resize(static_cast<std::size_t>(rows * dem.width));
        if (Status read = source.readWindow(0, y, dem.width, rows, samples); !read)
            return read.error();
        for (std::int64_t r = 0; r < rows; ++r) {
            const double latitude = g.originY - (double(y + r) + 0.5) * g.pixelSizeY;
            for (std::int64_t x = 0; x < dem.width; ++x) {
                const float h = samples[static_cast<std::size_t>(r * dem.width + x)];
                if (std::isnan(h)) continue;
                const double longitude = g.originX + (double(x) + 0.5) * g.pixelSizeX;
                const glm::dvec3 normal = globe::Wgs84::normalAt(latitude, longitude);
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
                        if (Status read = reader.readPatch(layoutPatchOf(id), patch.record); !read)
                            return Error{
                                fmt::format("source sample ({}, {}) lies in a patch that "
                                            "cannot be read: {}",
                                            x, y + r, read.error().message)};
                        patch.surface = std::make_unique<GlobePatchSurface>(id, layout.patchQuads(),
                                                                            patch.record.heights);
                        it = loaded.emplace(key, std::move(patch)).first;
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
                                {layoutPatchOf(id), x, y + r, distance, bound});
                    }
                }
            }
        }
        if (progress) progress(double(y + rows) / double(dem.height));
    }
    return report;
}

}  // namespace terrain::io
