#include "terrain/build/GlobePyramidBuilder.h"

#include "BuildClock.h"
#include "BuildFinish.h"
#include "BuildOutput.h"
#include "GeographicGrid.h"
#include "GlobePatchBuild.h"
#include "GlobeSources.h"
#include "NativeGrids.h"
#include "ParallelFor.h"
#include "WholeBuilds.h"
#include "terrain/build/GlobePatchSurface.h"
#include "terrain/globe/CubeSphere.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/GlobePatchErrors.h"
#include "terrain/pyramid/HeightCodes.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/ShardWriter.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace terrain::io {
namespace {

namespace fs = std::filesystem;
using globe::GlobePatchId;

using detail::idOf;
using detail::keyOf;
using detail::patchIndex;
using detail::PatchKey;

// Every source sample's place on the cube, computed once: the face and its coordinates.
struct SamplePlaces {
    std::vector<std::uint8_t> face;
    std::vector<double> s, t;
};

// A resampled source's own samples' places on the cube, from their latitudes and longitudes.
SamplePlaces placeOwnSamples(const GlobeSources::OwnSamples& own, unsigned threads) {
    SamplePlaces places;
    const auto count = static_cast<std::size_t>(own.width * own.height);
    places.face.resize(count);
    places.s.resize(count);
    places.t.resize(count);
    parallelFor(own.height, threads, [&](std::int64_t row) {
        for (std::int64_t col = 0; col < own.width; ++col) {
            const auto i = static_cast<std::size_t>(row * own.width + col);
            const globe::FacePoint p =
                globe::facePointOf(globe::Wgs84::normalAt(own.latitudes[i], own.longitudes[i]));
            places.face[i] = static_cast<std::uint8_t>(p.face);
            places.s[i] = p.s;
            places.t[i] = p.t;
        }
    });
    return places;
}

SamplePlaces placeSamples(const GeographicGrid& grid, unsigned threads) {
    SamplePlaces places;
    const auto count = static_cast<std::size_t>(grid.width() * grid.height());
    places.face.resize(count);
    places.s.resize(count);
    places.t.resize(count);
    parallelFor(grid.height(), threads, [&](std::int64_t row) {
        const double latitude = grid.latitudeOf(row);
        for (std::int64_t col = 0; col < grid.width(); ++col) {
            const auto i = static_cast<std::size_t>(row * grid.width() + col);
            const globe::FacePoint p =
                globe::facePointOf(globe::Wgs84::normalAt(latitude, grid.longitudeOf(col)));
            places.face[i] = static_cast<std::uint8_t>(p.face);
            places.s[i] = p.s;
            places.t[i] = p.t;
        }
    });
    return places;
}

struct LevelPatch {
    PatchRecord record;
    bool holdsSource = false;  // some source sample lies in it (else it only overlaps the extent)
    double measuredError = 0.0;
    double quantized = 0.0;  // the largest difference the quantizer made (lossy builds)
};

class GlobeBuilder {
public:
    GlobeBuilder(const GlobeSources& sources, const PyramidLayout& layout, int faceLevels,
                 const PyramidBuildOptions& options, const fs::path& folder)
        : m_sources(sources),
          m_layout(layout),
          m_finestFaceLevel(faceLevels),
          m_options(options),
          m_folder(folder),
          m_threads(options.threads != 0 ? options.threads
                                         : std::max(1u, std::thread::hardware_concurrency())) {
        m_shardOptions.compressionLevel = options.compressionLevel;
        if (options.maxErrorM > 0.0) m_quantization = ManifestQuantization{options.maxErrorM};
        m_levelMaxError.assign(static_cast<std::size_t>(layout.levelCount()), 0.0);
        m_presentPatches.assign(m_levelMaxError.size(), 0);
        m_presentShards.resize(m_levelMaxError.size());
    }

    Status run() {
        auto start = BuildClock::now();
        for (std::size_t k = 0; k < m_sources.sources().size(); ++k) {
            const GlobeSources::Source& source = m_sources.sources()[k];
            m_places.push_back(placeSamples(source.grid, m_threads));
            m_ownPlaces.push_back(
                source.own ? std::optional(placeOwnSamples(*source.own, m_threads)) : std::nullopt);
            m_taperSamples.push_back(taperSamples(k));
            m_measured.push_back(measuredSamples(k));
        }
        m_phases.readSeconds += secondsSince(start);
        std::unordered_map<PatchKey, float> finerErrors;
        std::unordered_set<PatchKey> finerKeys;
        for (int level = m_finestFaceLevel; level >= 0; --level) {
            if (m_options.cancel != nullptr && m_options.cancel->load())
                return Error{"the build was cancelled"};
            std::map<PatchKey, LevelPatch> patches;
            start = BuildClock::now();
            collectPatches(level, finerKeys, patches);
            m_phases.readSeconds += secondsSince(start);
            start = BuildClock::now();
            measureErrors(level, patches);
            // Each patch's bounds (λ(d) is most of a level's bounds time) on every thread,
            // then what the level gathers from them, in key order.
            std::vector<std::pair<const PatchKey, LevelPatch>*> ordered;
            ordered.reserve(patches.size());
            for (auto& entry : patches) ordered.push_back(&entry);
            parallelFor(std::ssize(ordered), m_threads, [&](std::int64_t i) {
                auto& [key, patch] = *ordered[static_cast<std::size_t>(i)];
                finishPatch(key, level, patch, finerKeys, finerErrors);
            });
            std::unordered_map<PatchKey, float> errors;
            for (auto& [key, patch] : patches) gatherPatch(key, level, patch, errors);
            m_phases.boundsSeconds += secondsSince(start);
            start = BuildClock::now();
            if (Status written = write(level, patches); !written) return written;
            m_phases.writeSeconds += secondsSince(start);
            finerKeys.clear();
            for (const auto& [key, patch] : patches) finerKeys.insert(key);
            finerErrors = std::move(errors);
            if (m_options.progress)
                m_options.progress(
                    {level + ManifestGlobe::kLevelOffset,
                     double(m_finestFaceLevel - level + 1) / double(m_finestFaceLevel + 1)});
        }
        return {};
    }

    const PyramidBuildPhases& phases() const { return m_phases; }
    std::int64_t patches() const { return m_patches; }
    const std::vector<double>& levelMaxError() const { return m_levelMaxError; }
    const std::vector<std::int64_t>& presentPatches() const { return m_presentPatches; }
    const std::vector<std::vector<ShardId>>& presentShards() const { return m_presentShards; }
    double rootError() const { return m_rootError; }
    /// Set for a lossy build, with the largest difference the finest level's quantizer made.
    const std::optional<ManifestQuantization>& quantization() const { return m_quantization; }

private:
    // The level's patches: every patch holding a source sample, and those of their
    // neighbours with a sample inside the source's extent (a patch can overlap the extent's
    // outer half pixel without holding a sample centre); at level 0 the six faces always.
    void collectPatches(int level, const std::unordered_set<PatchKey>& finerKeys,
                        std::map<PatchKey, LevelPatch>& patches) {
        const std::int64_t n = globe::patchesPerFaceSide(level);
        std::unordered_set<PatchKey> holding;
        for (std::size_t k = 0; k < m_places.size(); ++k) {
            if (m_sources.sources()[k].finestFaceLevel < level) continue;  // too coarse here
            const SamplePlaces& places = m_places[k];
            for (std::size_t i = 0; i < places.face.size(); ++i)
                holding.insert(
                    keyOf(places.face[i], patchIndex(places.s[i], n), patchIndex(places.t[i], n)));
        }
        std::unordered_set<PatchKey> candidates = holding;
        for (const PatchKey key : holding) detail::addPatchesAround(key, level, candidates);
        if (level == 0)
            for (int face = 0; face < globe::kCubeFaces; ++face)
                candidates.insert(keyOf(face, 0, 0));
        // Every present patch's parent exists, so the LOD can reach it from its face.
        std::unordered_set<PatchKey> parents;
        for (const PatchKey child : finerKeys) {
            const GlobePatchId id = idOf(child, level + 1);
            parents.insert(keyOf(id.face, id.x / 2, id.y / 2));
        }
        candidates.insert(parents.begin(), parents.end());

        std::vector<PatchKey> keys(candidates.begin(), candidates.end());
        std::vector<LevelPatch> built(keys.size());
        std::vector<std::uint8_t> keep(keys.size(), 0);
        parallelFor(std::ssize(keys), m_threads, [&](std::int64_t k) {
            const auto i = static_cast<std::size_t>(k);
            const bool insideAny = resample(idOf(keys[i], level), built[i].record, level);
            // A lossy build rounds the resampled heights here (Yusov §4), before Err(P) is
            // measured against the sources: the measured bound then covers the rounding.
            if (m_quantization)
                built[i].quantized = quantizeHeights(built[i].record.heights, halfStep(level));
            built[i].holdsSource = holding.contains(keys[i]);
            keep[i] = built[i].holdsSource || insideAny || level == 0 || parents.contains(keys[i]);
        });
        for (std::size_t i = 0; i < keys.size(); ++i)
            if (keep[i]) patches.emplace(keys[i], std::move(built[i]));

        // A present patch's siblings exist too (detail::forEachSibling): else the LOD draws their
        // quarters of the parent's tile, whose coarse cells ramp from a source's edge to the
        // bare ellipsoid in teeth as wide as the parent's cells.
        std::vector<PatchKey> siblings;
        for (const auto& [key, patch] : patches)
            detail::forEachSibling(key, level, [&](PatchKey sibling) {
                if (!patches.contains(sibling)) siblings.push_back(sibling);
            });
        std::sort(siblings.begin(), siblings.end());
        siblings.erase(std::unique(siblings.begin(), siblings.end()), siblings.end());
        std::vector<LevelPatch> added(siblings.size());
        parallelFor(std::ssize(siblings), m_threads, [&](std::int64_t k) {
            const auto i = static_cast<std::size_t>(k);
            resample(idOf(siblings[i], level), added[i].record, level);
            if (m_quantization)
                added[i].quantized = quantizeHeights(added[i].record.heights, halfStep(level));
        });
        for (std::size_t i = 0; i < siblings.size(); ++i)
            patches.emplace(siblings[i], std::move(added[i]));
    }

    // The patch's tile from the source; true when some drawn sample lies inside its extent.
    bool resample(const GlobePatchId& id, PatchRecord& record, int level) const {
        const int quads = m_layout.patchQuads();
        const int tile = m_layout.tileSamples();
        record.id = layoutPatchOf(id);
        record.heights.assign(static_cast<std::size_t>(tile * tile), 0.0f);
        record.valid.assign(record.heights.size(), 0);
        bool insideAny = false;
        const globe::PatchSampleDirections directions(id, quads, -1, quads + 1);
        for (int j = -1; j <= quads + 1; ++j) {
            for (int i = -1; i <= quads + 1; ++i) {
                const globe::Geodetic where = globe::Wgs84::geodeticOfNormal(directions(i, j));
                const GeographicGrid::Resampled value =
                    m_sources.at(where.latitudeDeg, where.longitudeDeg, level);
                const auto at = static_cast<std::size_t>((j + 1) * tile + i + 1);
                record.heights[at] = value.height;
                record.valid[at] = value.valid ? 1 : 0;
                const bool drawn = i >= 0 && j >= 0 && i <= quads && j <= quads;
                insideAny = insideAny || (drawn && value.inside);
            }
        }
        return insideAny;
    }

    // Err(P) measured at every source sample the composite shows (GlobeSources::measuredSample:
    // a resampled source's own samples, not its grid's): the distance along its normal to the
    // patch's triangles, whichever diagonal the tessellator draws. A sample whose patch of
    // this level does not exist (a coarse source, finer than its own finest level) is drawn
    // by an ancestor there, whose bound already holds it.
    void measureErrors(int level, std::map<PatchKey, LevelPatch>& patches) const {
        for (std::size_t k = 0; k < m_places.size(); ++k) {
            measureErrors(level, k, patches);
            measureTaper(level, m_taperSamples[k], patches);
        }
    }

    // Where a source's edge tapers to the bare ellipsoid (GeographicGrid::taperPlaces; not
    // where a coarser source lies beneath), the composite's heights: measured as the samples
    // are, so a coarse patch's ramp past the edge counts in its Err(P) and the LOD refines
    // along the edge until it is drawn within ε.
    struct TaperSample {
        glm::dvec3 normal{};
        double s = 0.0, t = 0.0;
        int face = 0;
        double height = 0.0;
    };
    std::vector<TaperSample> taperSamples(std::size_t k) const {
        std::vector<TaperSample> samples;
        for (const auto& [latitude, longitude] : m_sources.sources()[k].grid.taperPlaces()) {
            if (m_sources.beneath(k, latitude, longitude)) continue;
            TaperSample sample;
            sample.normal = globe::Wgs84::normalAt(latitude, longitude);
            const globe::FacePoint p = globe::facePointOf(sample.normal);
            sample.face = p.face;
            sample.s = p.s;
            sample.t = p.t;
            sample.height = double(m_sources.at(latitude, longitude, 0).height);
            samples.push_back(sample);
        }
        return samples;
    }

    void measureTaper(int level, const std::vector<TaperSample>& samples,
                      std::map<PatchKey, LevelPatch>& patches) const {
        const std::int64_t n = globe::patchesPerFaceSide(level);
        std::unordered_map<PatchKey, std::unique_ptr<GlobePatchSurface>> surfaces;
        for (const TaperSample& sample : samples) {
            const PatchKey key =
                keyOf(sample.face, patchIndex(sample.s, n), patchIndex(sample.t, n));
            const auto patch = patches.find(key);
            if (patch == patches.end()) continue;  // an ancestor draws it, and measured it
            auto& surface = surfaces[key];
            if (!surface)
                surface = std::make_unique<GlobePatchSurface>(
                    idOf(key, level), m_layout.patchQuads(), patch->second.record.heights,
                    GlobePatchSurface::Positions::RowsOnDemand);
            const auto [alongAD, alongBC] =
                surface->drawnHeights(sample.normal, {sample.face, sample.s, sample.t});
            patch->second.measuredError =
                std::max({patch->second.measuredError, std::abs(sample.height - alongAD),
                          std::abs(sample.height - alongBC)});
        }
    }

    // A source's measured samples as every level's measureErrors reads them, looked up in the
    // composite once (GlobeSources::measuredSample, a few % of a build a level), not at every
    // level: each sample's height (NaN where the source's sample is not measured) and the
    // terms of its normal. A grid's normal is Wgs84::normalAt of its row's latitude and its
    // column's longitude, so the rows' and columns' terms are kept (the same operations on
    // the same values: the same bits); a resampled source's own samples keep their places.
    struct MeasuredSamples {
        std::vector<double> heights;
        std::vector<double> cosLatitude, sinLatitude;       // per row (a grid)
        std::vector<globe::Wgs84::RadiiAlongNormal> radii;  // per row: the ellipsoid's there
        std::vector<double> cosLongitude, sinLongitude;     // per column (a grid)
        const GlobeSources::OwnSamples* own = nullptr;      // else per sample, from these
    };
    MeasuredSamples measuredSamples(std::size_t k) const {
        MeasuredSamples samples;
        const std::int64_t width = m_sources.measuredWidth(k);
        const std::int64_t height = m_sources.measuredHeight(k);
        samples.heights.resize(static_cast<std::size_t>(width * height));
        parallelFor(height, m_threads, [&](std::int64_t row) {
            for (std::int64_t col = 0; col < width; ++col) {
                const std::optional<GlobeSources::MeasuredSample> sample =
                    m_sources.measuredSample(k, col, row);
                samples.heights[static_cast<std::size_t>(row * width + col)] =
                    sample ? sample->height : std::numeric_limits<double>::quiet_NaN();
            }
        });
        const GlobeSources::Source& source = m_sources.sources()[k];
        if (source.own) {
            samples.own = &*source.own;
            return samples;
        }
        for (std::int64_t row = 0; row < height; ++row) {
            const double lat = source.grid.latitudeOf(row) * kDegree;
            samples.cosLatitude.push_back(std::cos(lat));
            samples.sinLatitude.push_back(std::sin(lat));
            samples.radii.push_back(
                globe::Wgs84::radiiAlongNormal(samples.sinLatitude.back(), 0.0));
        }
        for (std::int64_t col = 0; col < width; ++col) {
            const double lon = source.grid.longitudeOf(col) * kDegree;
            samples.cosLongitude.push_back(std::cos(lon));
            samples.sinLongitude.push_back(std::sin(lon));
        }
        return samples;
    }

    void measureErrors(int level, std::size_t k, std::map<PatchKey, LevelPatch>& patches) const {
        const SamplePlaces& places = m_ownPlaces[k] ? *m_ownPlaces[k] : m_places[k];
        const MeasuredSamples& measured = m_measured[k];
        const std::int64_t width = m_sources.measuredWidth(k);
        const std::int64_t height = m_sources.measuredHeight(k);
        const std::int64_t n = globe::patchesPerFaceSide(level);
        const int quads = m_layout.patchQuads();
        const std::int64_t rowsPerTask = 16;
        const std::int64_t tasks = (height + rowsPerTask - 1) / rowsPerTask;
        std::mutex merge;
        parallelFor(tasks, m_threads, [&](std::int64_t task) {
            std::unordered_map<PatchKey, std::unique_ptr<GlobePatchSurface>> surfaces;
            std::unordered_map<PatchKey, double> worst;
            const std::int64_t firstRow = task * rowsPerTask;
            for (std::int64_t row = firstRow; row < std::min(firstRow + rowsPerTask, height);
                 ++row) {
                for (std::int64_t col = 0; col < width; ++col) {
                    const auto i = static_cast<std::size_t>(row * width + col);
                    const double sampleHeight = measured.heights[i];
                    if (std::isnan(sampleHeight)) continue;
                    const PatchKey key = keyOf(places.face[i], patchIndex(places.s[i], n),
                                               patchIndex(places.t[i], n));
                    auto& surface = surfaces[key];
                    if (!surface) {
                        const auto patch = patches.find(key);
                        if (patch == patches.end()) continue;
                        surface = std::make_unique<GlobePatchSurface>(
                            idOf(key, level), quads, patch->second.record.heights,
                            GlobePatchSurface::Positions::RowsOnDemand);
                    }
                    glm::dvec3 normal, origin;
                    if (measured.own != nullptr) {
                        normal = globe::Wgs84::normalAt(measured.own->latitudes[i],
                                                        measured.own->longitudes[i]);
                        origin = globe::Wgs84::pointAlongNormal(normal, 0.0);
                    } else {
                        const auto r = static_cast<std::size_t>(row);
                        const auto c = static_cast<std::size_t>(col);
                        normal = {measured.cosLatitude[r] * measured.cosLongitude[c],
                                  measured.cosLatitude[r] * measured.sinLongitude[c],
                                  measured.sinLatitude[r]};
                        origin = globe::Wgs84::pointAlongNormal(normal, measured.radii[r]);
                    }
                    const auto [alongAD, alongBC] = surface->drawnHeights(
                        normal, globe::FacePoint{places.face[i], places.s[i], places.t[i]}, origin);
                    double& patchWorst = worst[key];
                    patchWorst = std::max({patchWorst, std::abs(sampleHeight - alongAD),
                                           std::abs(sampleHeight - alongBC)});
                }
            }
            const std::scoped_lock lock(merge);
            for (const auto& [key, error] : worst) {
                LevelPatch& patch = patches.at(key);
                patch.measuredError = std::max(patch.measuredError, error);
            }
        });
    }

    // Any thread: writes only `patch`.
    void finishPatch(PatchKey key, int level, LevelPatch& patch,
                     const std::unordered_set<PatchKey>& finerKeys,
                     const std::unordered_map<PatchKey, float>& finerErrors) const {
        const GlobePatchId id = idOf(key, level);
        double error = patch.measuredError;
        std::uint8_t presentChildren = 0;
        if (level < m_finestFaceLevel) {
            for (int child = 0; child < 4; ++child) {
                const PatchKey childKey =
                    keyOf(id.face, 2 * id.x + (child & 1), 2 * id.y + (child >> 1));
                if (!finerKeys.contains(childKey)) continue;
                presentChildren = static_cast<std::uint8_t>(presentChildren | (1u << child));
                error = std::max(error, double(finerErrors.at(childKey)));
            }
        }
        detail::finishGlobePatch(m_layout, level, error, presentChildren, m_quantization,
                                 patch.quantized, patch.record);
    }

    // After finishPatch, on the build's thread.
    void gatherPatch(PatchKey key, int level, const LevelPatch& patch,
                     std::unordered_map<PatchKey, float>& errors) {
        if (m_quantization && level == m_finestFaceLevel)
            m_quantization->finestLargestErrorM =
                std::max(m_quantization->finestLargestErrorM, patch.quantized);
        const PatchInfo& info = patch.record.info;
        errors[key] = info.error;
        if (level == 0) m_rootError = std::max(m_rootError, double(info.error));
    }

    Status write(int faceLevel, std::map<PatchKey, LevelPatch>& patches) {
        const int level = faceLevel + ManifestGlobe::kLevelOffset;
        std::map<std::pair<std::int64_t, std::int64_t>, std::vector<const PatchRecord*>> byShard;
        for (const auto& [key, patch] : patches) {
            const ShardId shard = m_layout.shardOf(patch.record.id);
            byShard[{shard.y, shard.x}].push_back(&patch.record);
        }
        for (const auto& [yx, records] : byShard) {
            const ShardId shard{level, yx.second, yx.first};
            if (Status written = detail::writeGlobeShard(m_folder, m_layout, shard, records,
                                                         m_shardOptions, m_quantization, m_threads);
                !written)
                return written;
            for (const PatchRecord* record : records)
                m_levelMaxError[static_cast<std::size_t>(level)] = std::max(
                    m_levelMaxError[static_cast<std::size_t>(level)], double(record->info.error));
            m_presentShards[static_cast<std::size_t>(level)].push_back(shard);
        }
        m_presentPatches[static_cast<std::size_t>(level)] = std::ssize(patches);
        m_patches += std::ssize(patches);
        return {};
    }

    // δ_l of a face level (layout level faceLevel + kLevelOffset).
    double halfStep(int faceLevel) const {
        return detail::globeHalfStep(*m_quantization, m_layout, faceLevel);
    }

    const GlobeSources& m_sources;
    const PyramidLayout& m_layout;
    int m_finestFaceLevel;
    const PyramidBuildOptions& m_options;
    fs::path m_folder;
    unsigned m_threads;
    ShardWriterOptions m_shardOptions;
    std::vector<SamplePlaces> m_places;  // one per source, in GlobeSources' order
    // A resampled source's own samples' places, where Err(P) is measured for it.
    std::vector<std::optional<SamplePlaces>> m_ownPlaces;
    std::vector<std::vector<TaperSample>> m_taperSamples;  // per source, as m_places
    std::vector<MeasuredSamples> m_measured;               // per source, as m_places
    PyramidBuildPhases m_phases;
    std::int64_t m_patches = 0;
    std::vector<double> m_levelMaxError;
    std::vector<std::int64_t> m_presentPatches;
    std::vector<std::vector<ShardId>> m_presentShards;
    double m_rootError = 0.0;
    std::optional<ManifestQuantization> m_quantization;  // a lossy build's
};

}  // namespace

namespace {

// Metres per unit of face coordinate at a place, the larger of the two directions.
double metresPerFaceUnit(double latitudeDeg, double longitudeDeg) {
    const globe::FacePoint p =
        globe::facePointOf(globe::Wgs84::normalAt(latitudeDeg, longitudeDeg));
    constexpr double kStep = 1e-6;
    const auto point = [&](double s, double t) {
        return globe::Wgs84::pointAlongNormal(globe::directionOf(p.face, s, t), 0.0);
    };
    const double s0 = std::clamp(p.s, kStep, 1.0 - kStep);
    const double t0 = std::clamp(p.t, kStep, 1.0 - kStep);
    return std::max(glm::distance(point(s0 - kStep, t0), point(s0 + kStep, t0)),
                    glm::distance(point(s0, t0 - kStep), point(s0, t0 + kStep))) /
           (2.0 * kStep);
}

}  // namespace

int globeFinestLevelFor(double spacingMetres, double latitudeDeg, double longitudeDeg, int quads) {
    const double rate = metresPerFaceUnit(latitudeDeg, longitudeDeg);
    const double patchesNeeded = rate / (double(quads) * spacingMetres);
    return std::max(0, static_cast<int>(std::ceil(std::log2(std::max(1.0, patchesNeeded)) - 1e-9)));
}

double globeFaceSampleSpacing(int faceLevel, double latitudeDeg, double longitudeDeg, int quads) {
    return metresPerFaceUnit(latitudeDeg, longitudeDeg) /
           (double(globe::patchesPerFaceSide(faceLevel)) * quads);
}

Result<PyramidBuildSummary> buildGlobePyramid(DemReader& reader, const fs::path& output,
                                              const PyramidBuildOptions& options) {
    DemReader* const readers[] = {&reader};
    return buildPyramid(PyramidSurface::Globe, readers, output, options);
}

Result<PyramidBuildSummary> buildGlobePyramid(std::span<DemReader* const> readers,
                                              const fs::path& output,
                                              const PyramidBuildOptions& options) {
    return buildPyramid(PyramidSurface::Globe, readers, output, options);
}

// The sources held whole, in half of the budget (the patches of a level the other half);
// decideBuildWay (BuildBudget.h) sends one geographic source too large for it shard by shard.
namespace detail {

Result<PyramidBuildSummary> buildWholeGlobePyramid(std::span<DemReader* const> readers,
                                                   const fs::path& output,
                                                   const PyramidBuildOptions& options) {
    const auto start = BuildClock::now();
    Result<GlobeSources> read =
        GlobeSources::read(readers, options.memoryBudgetBytes, options.patchSamples - 1,
                           options.globeOversampleLevels, 2);
    if (!read) return read.error();
    const GlobeSources& composite = read.value();
    BuildTotals totals;
    std::int64_t compositeValid = 0;
    for (const GlobeSources::Source& source : composite.sources()) {
        const GeographicGrid& g = source.grid;
        compositeValid += g.validSamples();
        if (composite.sources().size() > 1 && g.validSamples() == 0)
            totals.warnings.push_back(
                fmt::format("{}: no valid sample; it adds nothing", source.path));
        else if (g.validSamples() > 0)
            (void)checkCoverage(source.path, g.width() * g.height(), g.validSamples(),
                                totals.warnings);
    }
    if (compositeValid == 0) {
        const GeographicGrid& g = composite.sources().front().grid;
        return checkCoverage(readers.front()->info().path, g.width() * g.height(), 0,
                             totals.warnings)
            .error();
    }
    const int faceLevel = composite.finestFaceLevel();
    const DemInfo& first = readers.front()->info();
    Result<PyramidLayout> layout =
        globeLayout(faceLevel, options.patchSamples, options.blockQuads, options.shardPatches);
    if (!layout) return Error{first.path + ": " + layout.error().message};
    const PyramidLayout& l = layout.value();

    Result<PartialBuildFolder> created = PartialBuildFolder::create(output, options.overwrite);
    if (!created) return created.error();
    PartialBuildFolder& partial = created.value();
    GlobeBuilder builder(composite, l, faceLevel, options, partial.path());
    if (Status built = builder.run(); !built)
        return Error{first.path + ": " + built.error().message};

    // "Go to the data" goes to the finest source; the default flight visits each local one.
    std::vector<ManifestGlobeSource> extents;
    for (const GlobeSources::Source& source : composite.sources())
        extents.push_back(globeSourceOf(source.grid, source.path));
    if (options.globeNativeLeaves) {
        auto folders = buildNativeGrids(composite, partial.path(), options);
        if (!folders) return folders.error();
        for (std::size_t k = 0; k < extents.size(); ++k) extents[k].native = folders.value()[k];
    }
    PyramidManifest m = globeManifest(l, faceLevel, std::move(extents), readers);
    m.globe->seaLevelM = options.globeSeaLevelM;
    m.globe->oversampleLevels = options.globeOversampleLevels;
    double minHeight = 0.0, maxHeight = 0.0;
    bool any = false;
    for (std::size_t k = 0; k < composite.sources().size(); ++k) {
        // A resampled source's samples are its own, not its grid's.
        const GlobeSources::Source& source = composite.sources()[k];
        const GeographicGrid& g = source.grid;
        const std::int64_t samples =
            source.own ? source.own->width * source.own->height : g.width() * g.height();
        const std::int64_t valid = source.own ? source.own->validSamples : g.validSamples();
        const double low = source.own ? source.own->minHeight : g.minHeight();
        const double high = source.own ? source.own->maxHeight : g.maxHeight();
        m.noData.samples += samples - valid;
        // Every source of a composite, each with the no-data value it declared (theirs
        // differ: a global grid's and SRTM's); one source only where it had voids.
        if (composite.sources().size() > 1 || g.filledSamples() > 0)
            m.noData.sources.push_back(
                {source.path, source.noDataValue, true, g.filledSamples(), g.filledOverBeneath()});
        m.statistics.validSamples += valid;
        if (valid == 0) continue;
        minHeight = any ? std::min(minHeight, low) : low;
        maxHeight = any ? std::max(maxHeight, high) : high;
        any = true;
    }
    m.globe->seams = composite.seams();
    for (const ManifestSeam& seam : m.globe->seams)
        if (seam.cappedPixels > 0)
            totals.warnings.push_back(fmt::format(
                "{}: the height step at its edge (up to {:.0f} m) needs a blend band wider than "
                "a quarter of the source along {} pixels: the blend adds up to {:.2f} times the "
                "source's 99th-percentile slope over the band's width (seam slope {:.2f}, its "
                "99th-percentile slope {:.2f})",
                seam.input, seam.largestStepM, seam.cappedPixels, seam.bandScaleRatio,
                seam.seamSlope, seam.sourceSlopeP99));
    if (std::any_of(m.noData.sources.begin(), m.noData.sources.end(),
                    [](const ManifestSourceNoData& s) { return s.samples > 0; }))
        m.noData.fill = composite.sources().size() > 1 ? ManifestNoData::kDeltaSurfaceFill
                                                       : ManifestNoData::kMembraneFill;
    m.statistics.minHeight = minHeight;
    m.statistics.maxHeight = maxHeight;
    m.statistics.rootError = builder.rootError();
    for (ManifestLevel& level : m.levels) {
        const auto i = static_cast<std::size_t>(level.level);
        level.presentPatches = builder.presentPatches()[i];
        level.maxError = builder.levelMaxError()[i];
        level.presentShards = builder.presentShards()[i];
        std::sort(level.presentShards.begin(), level.presentShards.end(),
                  [](const ShardId& a, const ShardId& b) {
                      return std::pair(a.y, a.x) < std::pair(b.y, b.x);
                  });
    }
    m.quantization = builder.quantization();
    totals.patches = builder.patches();
    totals.phases = builder.phases();
    totals.seconds = secondsSince(start);
    auto summary = finishBuild(std::move(m), std::move(totals), partial.path());
    if (!summary) return summary.error();
    if (Status committed = partial.commit(); !committed) return committed.error();
    return summary;
}

}  // namespace detail
}  // namespace terrain::io
