// Globe pyramids (docs/pyramid-format.md, "Globe pyramids"): the layout that holds six faces,
// the build of geographic sources at the places a globe is hard (a high-latitude region, a cap
// over the north pole, a strip across the antimeridian, a whole-Earth grid with its repeated
// seam column), and what must hold for each: Err(P) bounds every valid source sample at every
// level (checked again from the files), shared edges are bit-identical across patches and
// cube edges, children masks match the patches on disk, and only patches near data exist.
#include "terrain/build/GlobePatchSurface.h"
#include "terrain/build/GlobePyramidBuilder.h"
#include "terrain/build/GlobeSourceSurface.h"
#include "terrain/build/PyramidSourceCheck.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeGroundHeight.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/pyramid/PyramidReader.h"

#include "FloatGeoTiff.h"
#include "GeographicFunctionDem.h"
#include "GlobeTestSources.h"
#include "SharedData.h"
#include "TempFolder.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <glm/geometric.hpp>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace terrain::io {
namespace {

using globe::GlobePatchId;
using globe::PatchSide;
using test::GeographicFunctionDem;
using test::hills;
using test::TempFolder;

PyramidBuildOptions smallPatches() { return test::smallGlobePatches(); }

struct Built {
    std::filesystem::path folder;
    PyramidBuildSummary summary;
};

Built build(DemReader& source, const TempFolder& temp, const std::string& name) {
    const std::filesystem::path out = temp.path() / (name + ".pyramid");
    auto built = buildGlobePyramid(source, out, smallPatches());
    EXPECT_TRUE(built) << (built ? "" : built.error().message);
    return {out, built ? built.value() : PyramidBuildSummary{}};
}

// Err(P) against every valid source sample, at every level, read back from the files.
void expectBoundsHold(const Built& built, DemReader& source) {
    auto report = checkErrorBoundsAgainstSource(built.folder, source);
    ASSERT_TRUE(report) << report.error().message;
    EXPECT_EQ(report.value().violationCount, 0);
    EXPECT_EQ(report.value().samplesChecked,
              built.summary.manifest.statistics.validSamples *
                  (built.summary.manifest.globe->faceFinestLevel + 1));
    for (const ErrorBoundViolation& v : report.value().violations)
        ADD_FAILURE() << "sample (" << v.x << ", " << v.y << ") is " << v.distanceM
                      << " m from patch L" << v.patch.level << " (" << v.patch.x << ", "
                      << v.patch.y << "), Err(P) " << v.boundM;
}

// Every present patch: its children mask matches the disk, and its shared edges with every
// present neighbour (across cube edges too) hold the same heights, bit for bit.
void expectConsistentPatches(const Built& built) {
    auto opened = PyramidReader::open(built.folder);
    ASSERT_TRUE(opened) << opened.error().message;
    PyramidReader& reader = opened.value();
    const PyramidLayout& layout = reader.layout();
    const int quads = layout.patchQuads();
    const int tile = layout.tileSamples();
    const int faceLevels = reader.manifest().globe->faceFinestLevel + 1;
    int edgesCompared = 0, crossFace = 0;
    for (int level = 0; level < faceLevels; ++level) {
        const std::int64_t n = globe::patchesPerFaceSide(level);
        for (int face = 0; face < globe::kCubeFaces; ++face) {
            for (std::int64_t y = 0; y < n; ++y) {
                for (std::int64_t x = 0; x < n; ++x) {
                    const GlobePatchId id{face, level, x, y};
                    auto info = reader.patchInfo(layoutPatchOf(id));
                    ASSERT_TRUE(info) << info.error().message;
                    if (!info.value().present) continue;
                    if (level + 1 < faceLevels) {
                        // All four children or none: a parent is never drawn in part by its
                        // own coarser tile (GlobePatchBuild.h, forEachSibling).
                        EXPECT_TRUE(info.value().presentChildren == 0 ||
                                    info.value().presentChildren == 0xF)
                            << "patch " << face << "/" << level << "/" << x << "/" << y
                            << " has children " << int(info.value().presentChildren);
                        for (int c = 0; c < 4; ++c) {
                            auto child = reader.patchInfo(layoutPatchOf(
                                {face, level + 1, 2 * x + (c & 1), 2 * y + (c >> 1)}));
                            ASSERT_TRUE(child);
                            EXPECT_EQ(child.value().present,
                                      ((info.value().presentChildren >> c) & 1) != 0);
                        }
                    }
                    auto mine = reader.readPatch(layoutPatchOf(id));
                    ASSERT_TRUE(mine) << mine.error().message;
                    for (const PatchSide side :
                         {PatchSide::Left, PatchSide::Right, PatchSide::Top, PatchSide::Bottom}) {
                        const globe::PatchNeighbour there = globe::neighbourOf(id, side);
                        auto theirInfo = reader.patchInfo(layoutPatchOf(there.id));
                        if (!theirInfo || !theirInfo.value().present) continue;
                        auto theirs = reader.readPatch(layoutPatchOf(there.id));
                        ASSERT_TRUE(theirs);
                        const auto at = [&](const std::vector<float>& h, PatchSide s, int k) {
                            const int i = s == PatchSide::Left    ? 0
                                          : s == PatchSide::Right ? quads
                                                                  : k;
                            const int j = s == PatchSide::Top      ? 0
                                          : s == PatchSide::Bottom ? quads
                                                                   : k;
                            return h[static_cast<std::size_t>((j + 1) * tile + i + 1)];
                        };
                        for (int k = 0; k <= quads; ++k)
                            ASSERT_EQ(at(mine.value().heights, side, k),
                                      at(theirs.value().heights, there.side,
                                         there.reversed ? quads - k : k))
                                << "face " << face << " level " << level << " (" << x << ", " << y
                                << ") side " << int(side) << " sample " << k;
                        ++edgesCompared;
                        crossFace += there.id.face != face;
                    }
                }
            }
        }
    }
    EXPECT_GT(edgesCompared, 0);
    ::testing::Test::RecordProperty("crossFaceEdges", crossFace);
}

TEST(GlobeLayout, FacesLieSideBySideBelowThreeEmptyLevels) {
    for (const int faceLevel : {0, 1, 5, 11}) {
        auto layout = globeLayout(faceLevel);
        ASSERT_TRUE(layout) << layout.error().message;
        EXPECT_EQ(layout.value().finestLevel(), faceLevel + ManifestGlobe::kLevelOffset);
        for (int l = 0; l <= faceLevel; ++l) {
            EXPECT_EQ(layout.value().patchesX(l + 3), 6 * globe::patchesPerFaceSide(l));
            EXPECT_EQ(layout.value().patchesY(l + 3), globe::patchesPerFaceSide(l));
        }
    }
    for (int level = 0; level <= 3; ++level)
        for (int face = 0; face < globe::kCubeFaces; ++face)
            for (std::int64_t y = 0; y < globe::patchesPerFaceSide(level); ++y)
                for (std::int64_t x = 0; x < globe::patchesPerFaceSide(level); ++x) {
                    const GlobePatchId id{face, level, x, y};
                    ASSERT_EQ(globePatchOf(layoutPatchOf(id)), id);
                }
    EXPECT_FALSE(globeLayout(31));
}

TEST(GlobePyramid, RegionalSourceAtHighLatitude) {
    TempFolder temp;
    // 0.5° × 0.25° at 60° N with a few voids.
    GeographicFunctionDem source(10.0, 60.25, 100, 50, 0.005, 0.005, [](double lat, double lon) {
        if (std::abs(lat - 60.1) < 0.006 && std::abs(lon - 10.2) < 0.02) return std::nanf("");
        return hills(lat, lon);
    });
    const Built built = build(source, temp, "regional");
    const PyramidManifest& m = built.summary.manifest;
    ASSERT_TRUE(m.globe);
    EXPECT_EQ(m.formatVersion, PyramidManifest::kGlobeFormatVersion);
    EXPECT_GE(m.globe->faceFinestLevel, 8);
    EXPECT_EQ(m.levels[3].presentPatches, 6);  // the six faces, always
    // Sparse: the finest level holds the region only, a sliver of the face.
    const std::int64_t finestPatches = m.levels.back().presentPatches;
    EXPECT_GT(finestPatches, 4);
    EXPECT_LT(finestPatches, 400);
    expectBoundsHold(built, source);
    auto reader = PyramidReader::open(built.folder);
    ASSERT_TRUE(reader);
    // Far from the data: absent, and said so.
    const GlobePatchId far{static_cast<int>(globe::CubeFace::South), 3, 2, 2};
    auto info = reader.value().patchInfo(layoutPatchOf(far));
    ASSERT_TRUE(info);
    EXPECT_FALSE(info.value().present);
    auto read = reader.value().readPatch(layoutPatchOf(far));
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find("absent"), std::string::npos) << read.error().message;
    // The manifest reads back as written.
    EXPECT_EQ(reader.value().manifest(), m);

    // Damage is named: a listed shard without its file, a manifest whose shard list or
    // tiling was edited.
    const std::string manifestText = toJson(m);
    const auto errorFor = [&](const std::string& from, const std::string& to) {
        std::string text = manifestText;
        const auto at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        text.replace(at, from.size(), to);
        auto parsed = fromJson(text, "manifest.json");
        return parsed ? std::string("no error") : parsed.error().message;
    };
    EXPECT_NE(errorFor("\"wgs84-tangent-cube\"", "\"geodetic\"").find("globe.tiling"),
              std::string::npos);
    const ManifestLevel& finest = m.levels.back();
    ASSERT_GE(finest.presentShards.size(), 2u);
    const ShardId& a = finest.presentShards[0];
    const ShardId& b = finest.presentShards[1];
    const std::string pair = fmt::format("[\n          {},\n          {}\n        ]", a.x, a.y);
    const std::string swapped = fmt::format("[\n          {},\n          {}\n        ]", b.x, b.y);
    EXPECT_NE(
        errorFor(pair + ",\n        " + swapped, swapped + ",\n        " + pair).find("not sorted"),
        std::string::npos);
    std::filesystem::remove(built.folder / m.layout.shardPath(a));
    auto reopened = PyramidReader::open(built.folder);
    ASSERT_TRUE(reopened);
    const PatchId inMissing{a.level, m.layout.shardFirstX(a), m.layout.shardFirstY(a)};
    auto missing = reopened.value().patchInfo(inMissing);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("the shard file is missing"), std::string::npos)
        << missing.error().message;
}

// A regional source alone on the globe, standing 300 m above the ellipsoid: its edge drops to
// the bare ellipsoid within one of its pixels beyond the extent, on every level the drop is
// held by Err(P) (so the LOD refines along the edge until it is drawn within ε), every
// present patch's siblings are present (so no coarse tile draws the drop in teeth), and
// beyond that pixel and one cell of the finest level nothing is drawn above the ellipsoid.
TEST(GlobePyramid, RegionalSourceAloneEndsAtItsExtent) {
    TempFolder temp;
    constexpr double kWest = 10.0, kNorth = 60.25, kPixel = 0.005;
    constexpr std::int64_t kWidth = 100, kHeight = 50;
    GeographicFunctionDem source(kWest, kNorth, kWidth, kHeight, kPixel, kPixel,
                                 [](double lat, double lon) { return hills(lat, lon) + 300.0f; });
    const Built built = build(source, temp, "alone");
    expectBoundsHold(built, source);
    expectConsistentPatches(built);
    auto reader = PyramidReader::open(built.folder);
    ASSERT_TRUE(reader) << reader.error().message;
    const int quads = reader.value().layout().patchQuads();
    const int finest = built.summary.manifest.globe->faceFinestLevel;
    // The drawn height (either diagonal) of the present patch of `level` at a place, and its
    // Err(P); nothing where that patch is absent.
    struct Drawn {
        double low = 0.0, high = 0.0, error = 0.0;
    };
    const auto drawnAt = [&](double lat, double lon, int level) -> std::optional<Drawn> {
        const glm::dvec3 normal = globe::Wgs84::normalAt(lat, lon);
        const globe::FacePoint p = globe::facePointOf(normal);
        const std::int64_t n = globe::patchesPerFaceSide(level);
        const GlobePatchId id{p.face, level,
                              std::min(static_cast<std::int64_t>(p.s * double(n)), n - 1),
                              std::min(static_cast<std::int64_t>(p.t * double(n)), n - 1)};
        auto info = reader.value().patchInfo(layoutPatchOf(id));
        if (!info || !info.value().present) return std::nullopt;
        auto record = reader.value().readPatch(layoutPatchOf(id));
        EXPECT_TRUE(record) << record.error().message;
        const auto [ad, bc] =
            GlobePatchSurface(id, quads, record.value().heights).drawnHeights(normal);
        return Drawn{std::min(ad, bc), std::max(ad, bc), double(record.value().info.error)};
    };
    // Along the four edges, a pixel beyond them, abreast of each edge pixel (where the build
    // measures, as it measures the source at its samples: GeographicGrid::taperPlaces), the
    // composite shows the ellipsoid, and every present patch's Err(P) holds that.
    int checked = 0;
    for (int k = 0; k < 50; ++k) {
        const double lon = kWest + (2 * k + 0.5) * kPixel, lat = kNorth - (k + 0.5) * kPixel;
        const double south = kNorth - kHeight * kPixel, east = kWest + kWidth * kPixel;
        const std::pair<double, double> beyond[] = {{kNorth + kPixel, lon},
                                                    {south - kPixel, lon},
                                                    {lat, kWest - kPixel},
                                                    {lat, east + kPixel}};
        for (const auto& [la, lo] : beyond)
            for (int level = 0; level <= finest; ++level) {
                const std::optional<Drawn> d = drawnAt(la, lo, level);
                if (!d) continue;
                ++checked;
                EXPECT_LE(std::max(std::abs(d->low), std::abs(d->high)), d->error + 1e-3)
                    << "a pixel beyond the edge at (" << la << ", " << lo << "), level " << level;
            }
        // Two pixels beyond (more than a pixel and a finest cell): the bare ellipsoid.
        const std::optional<Drawn> far = drawnAt(kNorth + 2.0 * kPixel, lon, finest);
        if (far) {
            EXPECT_NEAR(far->low, 0.0, 1e-3) << lon;
            EXPECT_NEAR(far->high, 0.0, 1e-3) << lon;
        }
    }
    EXPECT_GT(checked, 4 * 50);
}

// A lossy globe pyramid (terrain-build --globe --max-error-m): the stored heights are
// whole steps of 2δ_l, every patch's δ at least δ_l, and Err(P), measured on the stored
// surface, holds every source sample; the pyramid is smaller than the lossless one.
TEST(GlobePyramid, AStatedSeaLevelIsRecorded) {
    TempFolder temp;
    GeographicFunctionDem source(10.0, 60.25, 40, 20, 0.005, 0.005,
                                 [](double lat, double lon) { return hills(lat, lon) + 30.0f; });
    // Heights above the ellipsoid, say, where the sea lies 42.5 m up.
    PyramidBuildOptions options = smallPatches();
    options.globeSeaLevelM = 42.5;
    auto built = buildGlobePyramid(source, temp.path() / "sea.pyramid", options);
    ASSERT_TRUE(built) << built.error().message;
    EXPECT_EQ(built.value().manifest.globe->seaLevelM, 42.5);
    auto reread = readManifest(temp.path() / "sea.pyramid");
    ASSERT_TRUE(reread) << reread.error().message;
    EXPECT_EQ(reread.value().globe->seaLevelM, 42.5);
    // Mean sea level, the default, is not written: manifests from before read the same.
    nlohmann::json plain = nlohmann::json::parse(toJson(reread.value()));
    plain["globe"]["seaLevelM"] = 0.0;
    auto atZero = fromJson(plain.dump(), "m.json");
    ASSERT_TRUE(atZero) << atZero.error().message;
    EXPECT_EQ(nlohmann::json::parse(toJson(atZero.value()))["globe"].count("seaLevelM"), 0u);
    plain["globe"].erase("seaLevelM");
    auto without = fromJson(plain.dump(), "m.json");
    ASSERT_TRUE(without) << without.error().message;
    EXPECT_EQ(without.value().globe->seaLevelM, 0.0);
    plain["globe"]["seaLevelM"] = "high";
    auto refused = fromJson(plain.dump(), "m.json");
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("globe.seaLevelM"), std::string::npos)
        << refused.error().message;
}

// A source rough at its own samples (a hill plus a per-sample jitter, as SRTM's relief is):
// its finest face level resamples it, and the triangles between the face grid's samples cut
// across its own. Oversampled by one and two face levels, the finest level lies closer to the
// source's triangles (its Err(P), measured at every source sample, falls), every level still
// bounds every source sample, and the manifest says how far the build went below the source.
TEST(GlobePyramid, OversampledFinestLevelsLieCloserToTheSource) {
    TempFolder temp;
    GeographicFunctionDem source(10.0, 60.25, 60, 40, 0.005, 0.005, [](double lat, double lon) {
        const auto i = static_cast<std::uint32_t>(std::lround(lon / 0.005));
        const auto j = static_cast<std::uint32_t>(std::lround(lat / 0.005));
        const std::uint32_t hash = (i * 73856093u) ^ (j * 19349663u);
        return hills(lat, lon) + static_cast<float>(hash % 1000u) * 0.08f;
    });
    std::vector<double> finestError;
    int baseLevel = 0;
    for (int oversample = 0; oversample <= 2; ++oversample) {
        PyramidBuildOptions options = smallPatches();
        options.globeOversampleLevels = oversample;
        const std::string name = fmt::format("over{}", oversample);
        auto built = buildGlobePyramid(source, temp.path() / (name + ".pyramid"), options);
        ASSERT_TRUE(built) << built.error().message;
        const PyramidManifest& m = built.value().manifest;
        if (oversample == 0) baseLevel = m.globe->faceFinestLevel;
        EXPECT_EQ(m.globe->faceFinestLevel, baseLevel + oversample);
        EXPECT_EQ(m.globe->oversampleLevels, oversample);
        finestError.push_back(m.levels.back().maxError);
        expectBoundsHold({temp.path() / (name + ".pyramid"), built.value()}, source);
        auto reread = readManifest(temp.path() / (name + ".pyramid"));
        ASSERT_TRUE(reread) << reread.error().message;
        EXPECT_EQ(reread.value().globe->oversampleLevels, oversample);
    }
    RecordProperty("finestErrorM", fmt::format("{:.2f} {:.2f} {:.2f}", finestError[0],
                                               finestError[1], finestError[2]));
    EXPECT_LT(finestError[1], 0.75 * finestError[0]);
    EXPECT_LT(finestError[2], 0.75 * finestError[1]);

    // A manifest stating more levels below the sources than it has is refused by name.
    nlohmann::json j =
        nlohmann::json::parse(toJson(readManifest(temp.path() / "over1.pyramid").value()));
    j["globe"]["oversampleLevels"] = j["globe"]["faceFinestLevel"].get<int>() + 1;
    auto refused = fromJson(j.dump(), "m.json");
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("globe.oversampleLevels"), std::string::npos)
        << refused.error().message;
}

TEST(GlobePyramid, LossyRegionalSourceKeepsItsBounds) {
    TempFolder temp;
    GeographicFunctionDem source(10.0, 60.25, 100, 50, 0.005, 0.005, hills);
    const Built lossless = build(source, temp, "lossless");
    PyramidBuildOptions options = smallPatches();
    options.maxErrorM = 2.0;
    const std::filesystem::path out = temp.path() / "lossy.pyramid";
    auto made = buildGlobePyramid(source, out, options);
    ASSERT_TRUE(made) << made.error().message;
    const Built lossy{out, made.value()};
    const PyramidManifest& m = lossy.summary.manifest;
    ASSERT_TRUE(m.quantization);
    EXPECT_EQ(m.quantization->maxErrorM, 2.0);
    EXPECT_GT(m.quantization->finestLargestErrorM, 1.0);
    EXPECT_LE(m.quantization->finestLargestErrorM, 2.0 + 1e-3);
    EXPECT_LT(lossy.summary.bytes, lossless.summary.bytes);
    expectBoundsHold(lossy, source);

    // The present shards' patches only: the faces' finest levels hold far more absent ones.
    auto reader = PyramidReader::open(out);
    ASSERT_TRUE(reader) << reader.error().message;
    const PyramidLayout& layout = reader.value().layout();
    int patches = 0;
    for (const ManifestLevel& l : m.levels) {
        const int level = l.level;
        const double halfStep = m.quantization->halfStep(level, layout.finestLevel());
        for (const ShardId& shard : l.presentShards)
            for (std::int64_t y = layout.shardFirstY(shard);
                 y < layout.shardFirstY(shard) + layout.shardCountY(shard); ++y)
                for (std::int64_t x = layout.shardFirstX(shard);
                     x < layout.shardFirstX(shard) + layout.shardCountX(shard); ++x) {
                    auto info = reader.value().patchInfo({level, x, y});
                    ASSERT_TRUE(info);
                    if (!info.value().present) continue;
                    auto patch = reader.value().readPatch({level, x, y});
                    ASSERT_TRUE(patch) << patch.error().message;
                    const PatchInfo& i = patch.value().info;
                    EXPECT_GE(double(i.quantError), halfStep);
                    EXPECT_GE(i.error, i.approxError);  // measured on the stored surface
                    int offGrid = 0;
                    for (const float h : patch.value().heights) {
                        const double q = std::round(double(h) / (2.0 * halfStep));
                        offGrid += h == static_cast<float>(q * 2.0 * halfStep) ? 0 : 1;
                    }
                    EXPECT_EQ(offGrid, 0) << "L" << level << " (" << x << ", " << y << ")";
                    ++patches;
                }
    }
    EXPECT_GT(patches, 10);
}

TEST(GlobePyramid, CapOverTheNorthPole) {
    TempFolder temp;
    GeographicFunctionDem source(-180.0, 90.0, 360, 20, 1.0, 0.1,
                                 [](double lat, double lon) { return hills(lat, lon) + 200.0f; });
    const Built built = build(source, temp, "pole");
    expectBoundsHold(built, source);
    expectConsistentPatches(built);
}

// A global grid's edge row lies half a pixel short of the pole (ETOPO's at 89.83° S): between
// it and the pole the surface is a fan from each of the row's samples to one height, their
// mean, in the truth (GlobeSourceSurface) and in the pyramid alike. Clamping the rows instead
// met the pole at every height of the row at once (96 m apart here), a surface no patch can
// draw: the face grid's vertex at the pole took one of them, and the truth around it all.
TEST(GlobePyramid, TheSurfaceMeetsThePoleInOnePoint) {
    TempFolder temp;
    // The edge row's heights turn with the longitude (48 m either side of its mean).
    const auto rippled = [](double lat, double lon) {
        return hills(lat, lon) + 200.0f +
               48.0f * float(std::sin(3.0 * lon * std::numbers::pi / 180.0));
    };
    GeographicFunctionDem source(-180.0, 90.0, 360, 20, 1.0, 0.1, rippled);
    double rowSum = 0.0, rowLow = 1e9, rowHigh = -1e9;
    for (int col = 0; col < 360; ++col) {
        const double h = rippled(89.95, -179.5 + col);
        rowSum += h;
        rowLow = std::min(rowLow, h);
        rowHigh = std::max(rowHigh, h);
    }
    const double pole = rowSum / 360.0;
    ASSERT_GT(rowHigh - rowLow, 90.0);

    DemReader* const sources[] = {&source};
    auto truth = GlobeSourceSurface::read(sources, std::uint64_t{1} << 30, 32);
    ASSERT_TRUE(truth) << truth.error().message;
    // The spread round a parallel between the row and the pole: none at the pole, and the
    // fan's share of the row's beyond it (at 89.99°, a fifth of the way from the pole).
    const auto spreadAt = [&](double latitude) {
        double low = 1e9, high = -1e9;
        for (double lon = -180.0; lon < 180.0; lon += 0.37) {
            const auto [alongAD, alongBC] = truth.value().heightsAt(latitude, lon);
            low = std::min({low, alongAD, alongBC});
            high = std::max({high, alongAD, alongBC});
        }
        return std::pair{low, high};
    };
    const auto [atPoleLow, atPoleHigh] = spreadAt(90.0);
    EXPECT_NEAR(atPoleLow, pole, 1e-3);
    EXPECT_NEAR(atPoleHigh, pole, 1e-3);
    const auto [nearLow, nearHigh] = spreadAt(89.99);
    EXPECT_LE(nearHigh - nearLow, 0.2 * (rowHigh - rowLow) + 1e-3);
    EXPECT_GE(nearHigh - nearLow, 0.15 * (rowHigh - rowLow));
    // At the row itself the fan is the row (no step where it starts).
    for (int col = 0; col < 360; col += 7) {
        const double lon = -179.5 + col;
        EXPECT_NEAR(truth.value().heightsAt(89.95, lon).first, rippled(89.95, lon), 1e-3);
    }

    // The pyramid's finest face level stands on the same point: the pole is a vertex of it.
    const Built built = build(source, temp, "pole-fan");
    expectBoundsHold(built, source);
    auto query = GlobeGroundQuery::open(built.folder);
    ASSERT_TRUE(query) << query.error().message;
    for (const double lon : {-170.0, -60.0, 0.0, 45.0, 135.0}) {
        auto ground = query.value().at(90.0, lon);
        ASSERT_TRUE(ground) << ground.error().message;
        EXPECT_EQ(ground.value().faceLevel, built.summary.manifest.globe->faceFinestLevel);
        EXPECT_NEAR(ground.value().heightM, pole, 1e-3) << "longitude " << lon;
    }
}

TEST(GlobePyramid, StripAcrossTheAntimeridian) {
    TempFolder temp;
    // West edge at 179.8°: its eastern half lies at −179.9° … −179.8°.
    GeographicFunctionDem source(179.8, -29.8, 80, 40, 0.005, 0.005, hills);
    const Built built = build(source, temp, "antimeridian");
    expectBoundsHold(built, source);
    expectConsistentPatches(built);
}

TEST(GlobePyramid, WholeEarthWithRepeatedSeamColumnAcrossCubeEdges) {
    TempFolder temp;
    // 181 columns of 2°: the last repeats the first (as ETOPO's do), which the build accepts.
    GeographicFunctionDem source(-181.0, 90.0, 181, 90, 2.0, 2.0, hills);
    const Built built = build(source, temp, "earth");
    const PyramidManifest& m = built.summary.manifest;
    ASSERT_TRUE(m.globe);
    // Every patch of every level is present on a whole-Earth source.
    for (int l = 0; l <= m.globe->faceFinestLevel; ++l)
        EXPECT_EQ(m.levels[static_cast<std::size_t>(l + 3)].presentPatches,
                  6 * globe::patchesPerFaceSide(l) * globe::patchesPerFaceSide(l));
    expectBoundsHold(built, source);
    expectConsistentPatches(built);
}

// A fine regional source over a coarse global one (osgEarth's rule: the finer valid sample
// wins): deep levels exist only under the fine source, the bound holds for every sample the
// composite shows, the fine one's void follows the source beneath it (a source twice as
// coarse, 30 m lower: the delta-surface fill carries the 30 m in), and every shared edge
// still matches.
TEST(GlobePyramid, FineSourceCompositedOverACoarseGlobalOne) {
    TempFolder temp;
    GeographicFunctionDem coarse(-180.0, 90.0, 180, 90, 2.0, 2.0, hills);
    // 2° × 1° at 0.01°, 50 m above the coarse surface, with a void at (40.0, 21.0).
    GeographicFunctionDem fine(20.0, 40.5, 200, 100, 0.01, 0.01, [](double lat, double lon) {
        if (std::abs(lat - 40.0) < 0.03 && std::abs(lon - 21.0) < 0.03) return std::nanf("");
        return hills(lat, lon) + 50.0f;
    });
    // 0.02° around the void, 20 m above the coarse surface: the surface beneath the void.
    GeographicFunctionDem medium(20.2, 40.6, 80, 60, 0.02, 0.02,
                                 [](double lat, double lon) { return hills(lat, lon) + 20.0f; });
    // Each declares its own no-data value (a global grid's and SRTM's differ).
    coarse.setNoDataValue(-9.99e33);
    medium.setNoDataValue(std::nullopt);
    DemReader* const sources[] = {&coarse, &fine, &medium};
    const std::filesystem::path out = temp.path() / "composite.pyramid";
    auto built = buildGlobePyramid(sources, out, smallPatches());
    ASSERT_TRUE(built) << built.error().message;
    const PyramidManifest& m = built.value().manifest;
    const Built composite{out, built.value()};
    // The finest level holds the fine source's neighbourhood only.
    EXPECT_GT(m.globe->faceFinestLevel, 6);
    EXPECT_LT(m.levels.back().presentPatches, 600);
    EXPECT_NEAR(m.globe->west, 20.0, 1e-9);  // "go to the data" goes to the finest source
    EXPECT_EQ(m.statistics.validSamples, 180 * 90 + 200 * 100 - 6 * 6 + 80 * 60);
    // The void's samples, filled over the sources beneath it.
    EXPECT_EQ(m.noData.samples, 6 * 6);
    EXPECT_EQ(m.noData.fill, ManifestNoData::kDeltaSurfaceFill);
    // Every source, finest first, with the no-data value it declared and its filled samples
    // (issue 52: only the first source's value was kept, for the whole pyramid).
    ASSERT_EQ(m.noData.sources.size(), 3u);
    const std::optional<double> declared[] = {-32768.0, std::nullopt, -9.99e33};
    const std::int64_t filled[] = {6 * 6, 0, 0};
    for (std::size_t k = 0; k < 3; ++k) {
        const ManifestSourceNoData& source = m.noData.sources[k];
        EXPECT_TRUE(source.sourceValueRecorded) << k;
        EXPECT_EQ(source.sourceValue, declared[k]) << k;
        EXPECT_EQ(source.samples, filled[k]) << k;
        EXPECT_EQ(source.overBeneath, filled[k]) << k;
    }
    EXPECT_EQ(m.noData.sourceValue, -9.99e33);  // the first source given, as before
    // The seams of the fine and the medium source (each over the ones beneath), within their
    // slopes: written to the manifest, read back; one without them (before the band followed
    // the step) still opens.
    ASSERT_EQ(m.globe->seams.size(), 2u);
    for (const ManifestSeam& seam : m.globe->seams) {
        EXPECT_LE(seam.seamSlope, seam.sourceSlopeP99) << seam.input;
        EXPECT_GE(seam.bandPixels[0], 24.0) << seam.input;
    }
    EXPECT_GT(m.globe->seams[0].largestStepM, 50.0);  // the 2° grid misses the hills' ridges
    auto reread = readManifest(out);
    ASSERT_TRUE(reread) << reread.error().message;
    EXPECT_EQ(reread.value().globe->seams, m.globe->seams);
    // Every source's extent, finest first (issue 52: only the finest one's was kept, so the
    // default flight visited it alone); the finest's is sourceExtent.
    ASSERT_EQ(m.globe->sources.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k)
        EXPECT_EQ(m.globe->sources[k].input, m.noData.sources[k].input) << k;
    const auto extentOf = [](const ManifestGlobeSource& e) {
        return std::tuple(e.west, e.south, e.east, e.north);
    };
    EXPECT_EQ(extentOf(m.globe->sources[0]),
              std::tuple(m.globe->west, m.globe->south, m.globe->east, m.globe->north));
    const ManifestGlobeSource& mediumExtent = m.globe->sources[1];
    EXPECT_NEAR(mediumExtent.west, 20.2, 1e-9);
    EXPECT_NEAR(mediumExtent.east, 21.8, 1e-9);
    EXPECT_NEAR(mediumExtent.south, 39.4, 1e-9);
    EXPECT_NEAR(mediumExtent.north, 40.6, 1e-9);
    EXPECT_EQ(extentOf(m.globe->sources[2]), std::tuple(-180.0, -90.0, 180.0, 90.0));
    EXPECT_EQ(reread.value().globe->sources, m.globe->sources);
    nlohmann::json before = nlohmann::json::parse(toJson(m));
    before["globe"].erase("seams");
    before["globe"].erase("sources");
    // Nor each source's no-data value: of several sources, only the first one's is known.
    for (nlohmann::json& source : before["noData"]["sources"]) source.erase("sourceValue");
    auto old = fromJson(before.dump(), "manifest without seams");
    ASSERT_TRUE(old) << old.error().message;
    EXPECT_TRUE(old.value().globe->seams.empty());
    EXPECT_TRUE(old.value().globe->sources.empty());
    nlohmann::json badExtent = nlohmann::json::parse(toJson(m));
    badExtent["globe"]["sources"][1]["extent"] = {20.2, 40.6, 21.8, 39.4};  // south > north
    auto refused = fromJson(badExtent.dump(), "m.json");
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("m.json: globe.sources: "), std::string::npos)
        << refused.error().message;
    badExtent["globe"]["sources"][1]["extent"] = {20.2, 40.6};
    refused = fromJson(badExtent.dump(), "m.json");
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("globe.sources.extent"), std::string::npos)
        << refused.error().message;
    for (const ManifestSourceNoData& source : old.value().noData.sources)
        EXPECT_FALSE(source.sourceValueRecorded);
    EXPECT_FALSE(
        nlohmann::json::parse(toJson(old.value()))["noData"]["sources"][0].contains("sourceValue"));
    auto report = checkErrorBoundsAgainstSources(out, sources);
    ASSERT_TRUE(report) << report.error().message;
    EXPECT_EQ(report.value().violationCount, 0);
    EXPECT_GT(report.value().samplesChecked, 100 * 50 * m.globe->faceFinestLevel);
    // --verify --source checks the filled samples against the surface beneath them: drawn
    // within the 30 m between the sources at the void's rim (and Err(P)).
    EXPECT_EQ(report.value().filledSamplesChecked, 6 * 6);
    EXPECT_NEAR(report.value().largestRimDifferenceM, 30.0, 2.0);  // the medium one resampled
    EXPECT_LT(report.value().largestFilledDeviationM, 33.0);
    EXPECT_EQ(report.value().filledBeyondRimCount, 0);
    expectConsistentPatches(composite);

    // What a patch stores: the fine source inside it, in its void the medium one plus the
    // 30 m between them at the void's rim, and at its edge the coarse one: feathered in, no
    // step.
    auto reader = PyramidReader::open(out);
    ASSERT_TRUE(reader);
    const auto storedAt = [&](double lat, double lon, int level) {
        const glm::dvec3 normal = globe::Wgs84::normalAt(lat, lon);
        const globe::FacePoint p = globe::facePointOf(normal);
        const std::int64_t n = globe::patchesPerFaceSide(level);
        const GlobePatchId id{p.face, level, static_cast<std::int64_t>(p.s * double(n)),
                              static_cast<std::int64_t>(p.t * double(n))};
        auto record = reader.value().readPatch(layoutPatchOf(id));
        EXPECT_TRUE(record) << record.error().message;
        const GlobePatchSurface surface(id, reader.value().layout().patchQuads(),
                                        record.value().heights);
        return surface.drawnHeights(normal).first;
    };
    // The 2° grid between its pixel centres (odd degrees), on its cells' NW–SE diagonal.
    const auto coarseAt = [](double lat, double lon) {
        const double y = (89.0 - lat) / 2.0, x = (lon + 179.0) / 2.0;
        const double y0 = std::floor(y), x0 = std::floor(x), v = y - y0, u = x - x0;
        const auto h = [](double row, double col) {
            return double(hills(89.0 - 2.0 * row, -179.0 + 2.0 * col));
        };
        const double a = h(y0, x0), b = h(y0, x0 + 1), c = h(y0 + 1, x0), d = h(y0 + 1, x0 + 1);
        return u >= v ? a + u * (b - a) + v * (d - b) : a + v * (c - a) + u * (d - c);
    };
    const int finest = m.globe->faceFinestLevel;
    EXPECT_NEAR(storedAt(40.2, 20.8, finest), hills(40.2, 20.8) + 50.0, 3.0);
    // In the void, the medium source's shape at the fine one's height: no step at its rim.
    EXPECT_NEAR(storedAt(40.0, 21.0, finest), hills(40.0, 21.0) + 50.0, 3.0);
    EXPECT_NEAR(storedAt(40.0, 21.025, finest), hills(40.0, 21.025) + 50.0, 3.0);
    // At the fine source's north edge, beyond the medium one, the coarse surface: no step.
    EXPECT_NEAR(storedAt(40.4999, 21.9, finest), coarseAt(40.4999, 21.9), 3.0);
    EXPECT_NEAR(storedAt(40.5001, 21.9, finest), coarseAt(40.5001, 21.9), 3.0);

    // The ground a camera is placed over: the finest patch there, the higher diagonal.
    auto query = GlobeGroundQuery::open(out);
    ASSERT_TRUE(query) << query.error().message;
    const auto ground = [&](double lat, double lon) {
        auto g = query.value().at(lat, lon);
        EXPECT_TRUE(g) << g.error().message;
        return g ? g.value() : GlobeGround{};
    };
    const GlobeGround inFine = ground(40.2, 20.8);
    EXPECT_EQ(inFine.faceLevel, finest);
    EXPECT_NEAR(inFine.heightM, storedAt(40.2, 20.8, finest), 0.5);  // the finest sag is small
    EXPECT_NEAR(inFine.heightM, hills(40.2, 20.8) + 50.0, 3.0);
    // Far from the fine source: the coarse grid's own level, its surface.
    const GlobeGround inCoarse = ground(-30.0, 100.0);
    EXPECT_GE(inCoarse.faceLevel, 0);
    EXPECT_LT(inCoarse.faceLevel, finest - 3);
    {
        // Within that patch's Err(P) of the coarse grid's own surface (the face grid resamples
        // it), and in the tile's height range.
        const globe::FacePoint p = globe::facePointOf(globe::Wgs84::normalAt(-30.0, 100.0));
        const std::int64_t n = globe::patchesPerFaceSide(inCoarse.faceLevel);
        const GlobePatchId id{p.face, inCoarse.faceLevel,
                              static_cast<std::int64_t>(p.s * double(n)),
                              static_cast<std::int64_t>(p.t * double(n))};
        auto info = reader.value().patchInfo(layoutPatchOf(id));
        ASSERT_TRUE(info) << info.error().message;
        EXPECT_LE(std::abs(inCoarse.heightM - coarseAt(-30.0, 100.0)), info.value().error + 0.01);
        EXPECT_GE(inCoarse.heightM, info.value().minHeight);
        EXPECT_LE(inCoarse.heightM, info.value().maxHeight);
    }
}

TEST(GlobeGroundHeight, BareEllipsoidWhereThereIsNoData) {
    TempFolder temp;
    GeographicFunctionDem source(10.0, 60.25, 100, 50, 0.005, 0.005, hills);
    const Built built = build(source, temp, "regional");
    auto query = GlobeGroundQuery::open(built.folder);
    ASSERT_TRUE(query) << query.error().message;
    auto far = query.value().at(-45.0, -120.0);
    ASSERT_TRUE(far) << far.error().message;
    EXPECT_EQ(far.value().faceLevel, -1);
    EXPECT_EQ(far.value().heightM, 0.0);  // not the coarse face root's sag (km here)
    auto inside = query.value().at(60.1, 10.3);
    ASSERT_TRUE(inside) << inside.error().message;
    EXPECT_EQ(inside.value().faceLevel, built.summary.manifest.globe->faceFinestLevel);
    EXPECT_NEAR(inside.value().heightM, hills(60.1, 10.3), 5.0);
    // The same patch again comes from the one it kept; a neighbouring place too.
    EXPECT_EQ(query.value().at(60.1, 10.3).value().heightM, inside.value().heightM);
    EXPECT_NEAR(query.value().at(60.1001, 10.3).value().heightM, hills(60.1001, 10.3), 5.0);
}

// A projected DEM on the globe (issue 20): Kilauea's 30 m UTM grid, resampled onto a
// longitude/latitude grid by GDAL's warper, composited over ETOPO's 20′ global grid. Err(P)
// is measured against the UTM samples themselves, each placed through PROJ, so every one
// of them (not only the resampled grid's) is within the bound at every level, the finest
// levels' bounds are set by them (the tightest ratio is 1), and a metre of difference in
// them shows: the same pyramid checked against the source raised by 1 m fails.
TEST(GlobePyramid, ProjectedSourceIsBoundedAtItsOwnSamples) {
    TERRAIN_SHARED_DATA_OR_SKIP(kilauea, "kilauea_utm5n_30m.nc");
    TERRAIN_SHARED_DATA_OR_SKIP(etopo, "etopo20_global.nc");
    TempFolder temp;
    DemOpenOptions onTheGlobe;
    onTheGlobe.geographicGrid = true;
    const auto open = [&](const std::filesystem::path& path, const DemOpenOptions& options) {
        auto reader = openDem({path.string()}, options);
        EXPECT_TRUE(reader) << (reader ? "" : reader.error().message);
        return reader ? std::move(reader).value() : nullptr;
    };
    const auto utm = open(kilauea, onTheGlobe), global = open(etopo, onTheGlobe);
    ASSERT_TRUE(utm && global);
    ASSERT_TRUE(utm->info().resampledFrom);
    EXPECT_FALSE(global->info().resampledFrom);  // geographic already: read as it is
    const std::filesystem::path out = temp.path() / "kilauea.pyramid";
    PyramidBuildOptions options;
    options.threads = 2;
    options.compressionLevel = 1;
    DemReader* const sources[] = {utm.get(), global.get()};
    auto built = buildGlobePyramid(sources, out, options);
    ASSERT_TRUE(built) << built.error().message;
    const PyramidManifest& manifest = built.value().manifest;
    const int faceLevels = manifest.globe->faceFinestLevel + 1;
    EXPECT_EQ(faceLevels, 13);  // 30 m: face level 12 (19 m samples)

    auto report = checkErrorBoundsAgainstSources(out, sources);
    ASSERT_TRUE(report) << report.error().message;
    EXPECT_EQ(report.value().violationCount, 0);
    for (const ErrorBoundViolation& v : report.value().violations)
        ADD_FAILURE() << "sample (" << v.x << ", " << v.y << ") is " << v.distanceM
                      << " m from patch L" << v.patch.level << ", Err(P) " << v.boundM;
    // Kilauea's 658,945 valid UTM samples (857 × 793 less 20,656 voids) at 13 levels, and
    // ETOPO's where it shows, at levels 0 to its own finest.
    EXPECT_GT(report.value().samplesChecked, std::int64_t{658945} * faceLevels);
    const std::vector<double>& ratio = report.value().tightestRatio;
    EXPECT_GT(ratio.back(), 0.999);  // the finest bound is the worst UTM sample's distance

    DemOpenOptions raised = onTheGlobe;
    raised.verticalOffset = 1.0;
    const auto higher = open(kilauea, raised);
    ASSERT_TRUE(higher);
    DemReader* const higherSources[] = {higher.get(), global.get()};
    auto off = checkErrorBoundsAgainstSources(out, higherSources);
    ASSERT_TRUE(off) << off.error().message;
    EXPECT_GT(off.value().violationCount, 0);
}

// Hundreds of metres of smooth relief over tens of kilometres, in a projection's metres.
double projectedRelief(double x, double y) {
    return 1200.0 + 500.0 * std::sin(x / 70e3 + 0.7) * std::cos(y / 90e3 - 0.4) +
           200.0 * std::sin((x + 2.0 * y) / 150e3 + 1.1);
}

// A `width` × `height` GeoTIFF of projectedRelief in EPSG `epsg`, opened onto the globe's
// longitude/latitude grid and built: every own sample within Err(P) at every level, and at
// each of `places` (latitude, longitude) the finest level's surface within its bound of the
// relief there. Returns the grid it went onto.
DemInfo expectProjectedSourceBuilds(const std::string& name, int epsg,
                                    const std::array<double, 6>& geoTransform, int width,
                                    int height,
                                    const std::vector<std::pair<double, double>>& places) {
    TempFolder temp;
    std::vector<float> samples;
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c)
            samples.push_back(static_cast<float>(
                projectedRelief(geoTransform[0] + (c + 0.5) * geoTransform[1],
                                geoTransform[3] + (r + 0.5) * geoTransform[5])));
    const std::string tiff = test::writeFloatGeoTiff(temp.file(name + ".tif"), geoTransform, width,
                                                     height, samples, std::nullopt, epsg);
    DemOpenOptions onTheGlobe;
    onTheGlobe.geographicGrid = true;
    auto opened = openDem({tiff}, onTheGlobe);
    EXPECT_TRUE(opened) << opened.error().message;
    if (!opened) return {};
    DemReader& source = *opened.value();
    EXPECT_TRUE(source.info().resampledFrom);

    const Built built = build(source, temp, name);
    const PyramidManifest& manifest = built.summary.manifest;
    EXPECT_TRUE(manifest.globe);
    if (!manifest.globe) return source.info();
    EXPECT_EQ(manifest.statistics.validSamples, std::int64_t{width} * height);
    expectBoundsHold(built, source);
    auto report = checkErrorBoundsAgainstSource(built.folder, source);
    EXPECT_TRUE(report) << report.error().message;
    if (report) {
        EXPECT_GT(report.value().tightestRatio.back(), 0.999);  // set by own samples
    }

    OGRSpatialReference wgs84, projected;
    wgs84.importFromEPSG(4326);
    projected.importFromEPSG(epsg);
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    projected.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    const std::unique_ptr<OGRCoordinateTransformation> toProjected(
        OGRCreateCoordinateTransformation(&wgs84, &projected));
    EXPECT_TRUE(toProjected);
    auto query = GlobeGroundQuery::open(built.folder);
    EXPECT_TRUE(query) << query.error().message;
    if (!toProjected || !query) return source.info();
    const double finestBound = manifest.levels.back().maxError;
    for (const auto& [latitude, longitude] : places) {
        double x = longitude, y = latitude;
        EXPECT_TRUE(toProjected->Transform(1, &x, &y));
        auto ground = query.value().at(latitude, longitude);
        EXPECT_TRUE(ground) << ground.error().message;
        if (!ground) continue;
        EXPECT_EQ(ground.value().faceLevel, manifest.globe->faceFinestLevel)
            << latitude << "°, " << longitude << "°";
        EXPECT_NEAR(ground.value().heightM, projectedRelief(x, y), finestBound + 1.0)
            << latitude << "°, " << longitude << "°";
    }
    return source.info();
}

// A polar stereographic DEM (Antarctica's EPSG:3031, the Arctic's EPSG:3413: issue 52) spans
// every longitude around its pole. It goes onto a longitude/latitude grid wrapping all 360°
// with an edge on the pole, its own samples (one of them on the pole) are within Err(P) at
// every level, and at and around the pole the surface is the source's, not a hole down to the
// ellipsoid.
void expectPolarGridBuilds(int epsg, double poleLatitude) {
    // 201 × 201 samples of 5 km around the pole, the middle one on it.
    constexpr int kSide = 201;
    constexpr double kPixelM = 5000.0, kHalfM = 0.5 * kSide * kPixelM;
    std::vector<std::pair<double, double>> places;
    const double towardsEquator = poleLatitude > 0.0 ? -1.0 : 1.0;
    for (const double fromPole : {0.0, 0.01, 0.2, 2.0})
        for (const double longitude : {-180.0, -135.0, -45.0, 0.0, 30.0, 90.0, 179.9})
            places.emplace_back(poleLatitude + towardsEquator * fromPole, longitude);
    const DemInfo grid = expectProjectedSourceBuilds(
        fmt::format("polar-{}", epsg), epsg, {-kHalfM, kPixelM, 0.0, kHalfM, 0.0, -kPixelM},
        kSide, kSide, places);
    const Georeference& geo = grid.georeference;
    EXPECT_NEAR(double(grid.width) * geo.pixelSizeX, 360.0, 1e-9);
    EXPECT_NEAR(poleLatitude > 0.0 ? geo.originY
                                   : geo.originY - double(grid.height) * geo.pixelSizeY,
                poleLatitude, 1e-9);
}

TEST(GlobePyramid, ProjectedSourceOverTheSouthPole) { expectPolarGridBuilds(3031, -90.0); }

TEST(GlobePyramid, ProjectedSourceOverTheNorthPole) { expectPolarGridBuilds(3413, 90.0); }

// A UTM zone 60 grid (central meridian 177° E) 320 to 440 km east of it, near the equator: its
// samples lie on both sides of 180°, and its grid runs on past 180° as one interval.
TEST(GlobePyramid, ProjectedSourceAcrossTheAntimeridian) {
    std::vector<std::pair<double, double>> places;
    for (const double longitude : {179.95, 180.0, -179.95, -179.5})
        places.emplace_back(0.5, longitude);
    const DemInfo grid = expectProjectedSourceBuilds(
        "antimeridian", 32660, {820000.0, 2000.0, 0.0, 80000.0, 0.0, -2000.0}, 60, 30, places);
    const Georeference& geo = grid.georeference;
    EXPECT_LT(geo.originX, 180.0);
    EXPECT_GT(geo.originX + double(grid.width) * geo.pixelSizeX, 180.0);
}

TEST(GlobePyramid, RefusesSourcesThatAreNotGeographic) {
    TempFolder temp;
    GeographicFunctionDem source(0.0, 0.0, 10, 10, 1.0, 1.0, hills);
    auto projected = source.info();
    struct Projected final : DemReader {
        DemInfo info_;
        const DemInfo& info() const override { return info_; }
        Status readWindow(std::int64_t, std::int64_t, std::int64_t, std::int64_t,
                          std::span<float>) override {
            return {};
        }
    } reader;
    reader.info_ = projected;
    reader.info_.georeference.crsKind = CrsKind::Projected;
    auto built = buildGlobePyramid(reader, temp.path() / "x.pyramid", smallPatches());
    ASSERT_FALSE(built);
    EXPECT_NE(built.error().message.find("geographic-function-dem: a globe pyramid needs a "
                                         "geographic"),
              std::string::npos)
        << built.error().message;
    EXPECT_FALSE(std::filesystem::exists(temp.path() / "x.pyramid"));
}

// The surface the errors are measured on, checked by geometry alone: the piercing point lies
// on a plane through three of the cell's corners, sample normals pierce at the sample's height,
// and a level patch sags between samples by no more than the flat-triangle bound.
TEST(GlobePatchSurface, PiercesTheDrawnTrianglesAlongTheNormal) {
    const int quads = 8;
    const int tile = quads + 3;
    for (const GlobePatchId id :
         {GlobePatchId{0, 0, 0, 0}, GlobePatchId{4, 6, 31, 32}, GlobePatchId{2, 12, 2048, 2047}}) {
        std::vector<float> flat(static_cast<std::size_t>(tile * tile), 250.0f);
        const GlobePatchSurface surface(id, quads, flat);
        for (int j = 0; j <= quads; ++j)
            for (int i = 0; i <= quads; ++i) {
                const auto [a, b] =
                    surface.drawnHeights(globe::patchSampleDirection(id, quads, i, j));
                EXPECT_NEAR(a, 250.0, 1e-6);
                EXPECT_NEAR(b, 250.0, 1e-6);
            }
        const double sag =
            globe::flatTriangleErrorBound(globe::maxSampleSpacing(id.level, quads), 250.0);
        for (int k = 0; k < 50; ++k) {
            const globe::FacePoint p =
                globe::patchPoint(id, (k % 7 + 0.37) / 7.0, (k / 7 % 7 + 0.61) / 7.0);
            const auto [a, b] = surface.drawnHeights(globe::directionOf(p.face, p.s, p.t));
            EXPECT_LE(a, 250.0 + 1e-6);
            EXPECT_GE(a, 250.0 - sag);
            EXPECT_LE(b, 250.0 + 1e-6);
            EXPECT_GE(b, 250.0 - sag);
        }
    }
}

// The builders pass the face point they already have (globe::facePointOf, clamped to the
// face) to drawnHeights, and the whole build the normal's ellipsoid point from its row's radii
// too, to a surface making its rows on demand: the same heights to the bit as projecting the
// normal again on a surface made whole, inside the patch, on its border and on the cube's
// edges, where facePointOf clamps.
TEST(GlobePatchSurface, DrawnHeightsFromAFacePointAreTheSameToTheBit) {
    const int quads = 8;
    const int tile = quads + 3;
    std::vector<float> rough(static_cast<std::size_t>(tile * tile));
    for (std::size_t k = 0; k < rough.size(); ++k)
        rough[k] = 100.0f + 37.0f * float((k * 7919) % 23) - 0.125f * float(k % 5);
    int onEdges = 0;
    for (const GlobePatchId id : {GlobePatchId{0, 0, 0, 0}, GlobePatchId{3, 1, 1, 0},
                                  GlobePatchId{5, 7, 0, 127}, GlobePatchId{1, 12, 4095, 4095}}) {
        const GlobePatchSurface surface(id, quads, rough);
        const GlobePatchSurface onDemand(id, quads, rough,
                                         GlobePatchSurface::Positions::RowsOnDemand);
        for (int k = 0; k <= 400; ++k) {
            // A grid over the patch, its border included.
            const double u = (k % 21) / 20.0, v = (k / 21 % 21) / 20.0;
            const globe::FacePoint place = globe::patchPoint(id, u, v);
            const glm::dvec3 normal = globe::directionOf(place.face, place.s, place.t);
            const globe::FacePoint p = globe::facePointOf(normal);
            if (p.face != id.face) continue;  // a cube edge owned by the other face
            onEdges += p.s == 0.0 || p.s == 1.0 || p.t == 0.0 || p.t == 1.0;
            const auto projected = surface.drawnHeights(normal);
            const auto given = surface.drawnHeights(normal, p);
            ASSERT_TRUE(projected == given)
                << "face " << id.face << " level " << id.level << " at " << u << "," << v;
            const glm::dvec3 origin = globe::Wgs84::pointAlongNormal(
                normal, globe::Wgs84::radiiAlongNormal(normal.z, 0.0));
            ASSERT_TRUE(onDemand.drawnHeights(normal, p, origin) == projected)
                << "face " << id.face << " level " << id.level << " at " << u << "," << v;
        }
    }
    EXPECT_GT(onEdges, 0);  // clamped face points were among them
}

}  // namespace
}  // namespace terrain::io
