// The procedural DEM: determinism, window independence, thread independence, and the
// features it promises (exact cliff, single-sample spikes, bit-flat lake, flat mesa tops)
// at the default size and on DEMs of 2^20 and 2^32 samples a side.
#include "terrain/source/ProceduralTerrain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace terrain::io {
namespace {

constexpr std::int64_t k2To20 = std::int64_t{1} << 20;
constexpr std::int64_t k2To32 = std::int64_t{1} << 32;

ProceduralTerrain makeTerrain(std::int64_t side = 1025, std::uint64_t seed = 1) {
    ProceduralTerrainParameters p;
    p.widthSamples = side;
    p.heightSamples = side;
    p.seed = seed;
    Result<ProceduralTerrain> t = ProceduralTerrain::create(p);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    return std::move(t).value();
}

std::vector<float> window(const ProceduralTerrain& t, std::int64_t x0, std::int64_t y0,
                          std::int64_t w, std::int64_t h, unsigned threads = 1) {
    std::vector<float> out(static_cast<std::size_t>(w * h));
    t.fillWindow(x0, y0, w, h, out, threads);
    return out;
}

bool bitEqual(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(ProceduralTerrain, DefaultsAreA1025SquareAt30Metres) {
    const ProceduralTerrainParameters p;
    EXPECT_EQ(p.widthSamples, 1025);
    EXPECT_EQ(p.heightSamples, 1025);
    EXPECT_EQ(p.sampleSpacingM, 30.0);
    const ProceduralTerrain t = makeTerrain();
    // Octaves reach a wavelength of 2 to 4 samples: 1024 / (2 · 2^8) = 2.
    EXPECT_EQ(t.octaves(), 9);
    EXPECT_EQ(makeTerrain(k2To20 + 1).octaves(), 19);
}

TEST(ProceduralTerrain, SameSeedGivesBitIdenticalSamplesAndOtherSeedsDiffer) {
    const ProceduralTerrain a = makeTerrain(1025, 7);
    const ProceduralTerrain b = makeTerrain(1025, 7);
    const ProceduralTerrain c = makeTerrain(1025, 8);
    const std::vector<float> wa = window(a, 0, 0, 1025, 1025);
    const std::vector<float> wb = window(b, 0, 0, 1025, 1025);
    const std::vector<float> wc = window(c, 0, 0, 1025, 1025);
    EXPECT_EQ(std::memcmp(wa.data(), wb.data(), wa.size() * sizeof(float)), 0);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < wa.size(); ++i) differing += bitEqual(wa[i], wc[i]) ? 0 : 1;
    EXPECT_GT(differing, wa.size() * 9 / 10);
    EXPECT_NE(a.cliffColumn(0), c.cliffColumn(0));
    ASSERT_FALSE(a.spikes().empty());
    ASSERT_FALSE(c.spikes().empty());
    EXPECT_NE(a.spikes()[0].x * 100000 + a.spikes()[0].y,
              c.spikes()[0].x * 100000 + c.spikes()[0].y);
}

// Random pairs of overlapping windows must agree bit for bit on their overlap.
void expectOverlapsAgree(const ProceduralTerrain& t, std::int64_t nearX, std::int64_t nearY,
                         std::int64_t spread, int pairs) {
    std::mt19937_64 rng(1234);
    const auto pick = [&](std::int64_t lo, std::int64_t hi) {
        return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng);
    };
    for (int i = 0; i < pairs; ++i) {
        const std::int64_t aw = pick(1, 90), ah = pick(1, 90);
        const std::int64_t ax =
            std::clamp<std::int64_t>(nearX + pick(-spread, spread), 0, t.width() - aw);
        const std::int64_t ay =
            std::clamp<std::int64_t>(nearY + pick(-spread, spread), 0, t.height() - ah);
        const std::int64_t bw = pick(1, 90), bh = pick(1, 90);
        const std::int64_t bx =
            std::clamp<std::int64_t>(ax + pick(-bw + 1, aw - 1), 0, t.width() - bw);
        const std::int64_t by =
            std::clamp<std::int64_t>(ay + pick(-bh + 1, ah - 1), 0, t.height() - bh);
        const std::vector<float> a = window(t, ax, ay, aw, ah);
        const std::vector<float> b = window(t, bx, by, bw, bh);
        std::int64_t compared = 0;
        for (std::int64_t y = std::max(ay, by); y < std::min(ay + ah, by + bh); ++y) {
            for (std::int64_t x = std::max(ax, bx); x < std::min(ax + aw, bx + bw); ++x) {
                const float va = a[static_cast<std::size_t>((y - ay) * aw + (x - ax))];
                const float vb = b[static_cast<std::size_t>((y - by) * bw + (x - bx))];
                ASSERT_TRUE(bitEqual(va, vb))
                    << "sample (" << x << ", " << y << "): " << va << " vs " << vb;
                ++compared;
            }
        }
        EXPECT_GT(compared, 0);
    }
}

TEST(ProceduralTerrain, OverlappingWindowsAgreeExactly) {
    const ProceduralTerrain t = makeTerrain();
    expectOverlapsAgree(t, 512, 512, 512, 60);
    // Around the fault, where the east block is the relief shifted by one column.
    expectOverlapsAgree(t, t.cliffColumn(500), 500, 40, 30);
}

TEST(ProceduralTerrain, OverlappingWindowsAgreeNear2To20) {
    const ProceduralTerrain t = makeTerrain(k2To20 + 1);
    expectOverlapsAgree(t, k2To20 - 50, k2To20 - 50, 60, 20);
    expectOverlapsAgree(t, k2To20 / 2, k2To20 / 3, 1000, 20);
}

TEST(ProceduralTerrain, OverlappingWindowsAgreeNear2To32) {
    const ProceduralTerrain t = makeTerrain(2 * k2To32 + 1);
    expectOverlapsAgree(t, k2To32, k2To32, 100, 15);
    expectOverlapsAgree(t, 2 * k2To32 - 60, 60, 60, 10);
}

TEST(ProceduralTerrain, FillWindowEqualsPerSampleEvaluation) {
    for (const std::int64_t side : {std::int64_t{1025}, k2To20 + 1, 2 * k2To32 + 1}) {
        const ProceduralTerrain t = makeTerrain(side);
        std::mt19937_64 rng(99);
        for (int i = 0; i < 8; ++i) {
            const std::int64_t w = 37, h = 23;
            const std::int64_t x0 = std::uniform_int_distribution<std::int64_t>(0, side - w)(rng);
            const std::int64_t y0 = std::uniform_int_distribution<std::int64_t>(0, side - h)(rng);
            const std::vector<float> win = window(t, x0, y0, w, h);
            for (std::int64_t y = 0; y < h; ++y)
                for (std::int64_t x = 0; x < w; ++x)
                    ASSERT_TRUE(bitEqual(win[static_cast<std::size_t>(y * w + x)],
                                         t.sample(x0 + x, y0 + y)))
                        << "side " << side << " sample (" << x0 + x << ", " << y0 + y << ")";
        }
    }
    // Every spike and its neighbourhood, where fillWindow patches samples in.
    const ProceduralTerrain t = makeTerrain();
    for (const TerrainSpike& s : t.spikes()) {
        const std::vector<float> win = window(t, s.x - 2, s.y - 2, 5, 5);
        for (std::int64_t y = 0; y < 5; ++y)
            for (std::int64_t x = 0; x < 5; ++x)
                ASSERT_TRUE(bitEqual(win[static_cast<std::size_t>(y * 5 + x)],
                                     t.sample(s.x - 2 + x, s.y - 2 + y)));
    }
}

TEST(ProceduralTerrain, ThreadCountDoesNotChangeHeights) {
    const ProceduralTerrain t = makeTerrain();
    const std::vector<float> one = window(t, 3, 5, 1000, 1010, 1);
    for (const unsigned threads : {2U, 3U, 7U, 0U}) {
        const std::vector<float> many = window(t, 3, 5, 1000, 1010, threads);
        EXPECT_EQ(std::memcmp(one.data(), many.data(), one.size() * sizeof(float)), 0)
            << threads << " threads";
    }
}

// In every row the fault drops by exactly the cliff height between two adjacent samples,
// and it is a step: the samples beside it on either side differ far less.
void expectExactCliff(const ProceduralTerrain& t, std::int64_t rowStep) {
    ASSERT_TRUE(t.hasCliff());
    const float cliff = t.cliffHeightM();
    EXPECT_EQ(cliff, 1000.0F);
    std::int64_t rows = 0;
    for (std::int64_t y = 0; y < t.height(); y += rowStep) {
        const std::int64_t c = t.cliffColumn(y);
        ASSERT_GE(c, 1);
        ASSERT_LE(c, t.width() - 3);
        const std::vector<float> row = window(t, c - 1, y, 4, 1);
        ASSERT_EQ(row[1] - row[2], cliff) << "row " << y << " column " << c;
        EXPECT_LT(std::abs(row[0] - row[1]), 0.5F * cliff) << "row " << y;
        EXPECT_LT(std::abs(row[2] - row[3]), 0.5F * cliff) << "row " << y;
        ++rows;
    }
    EXPECT_GT(rows, 500);
}

TEST(ProceduralTerrain, CliffDropsByItsFullHeightBetweenAdjacentSamplesInEveryRow) {
    expectExactCliff(makeTerrain(), 1);
    expectExactCliff(makeTerrain(1025, 12345), 1);
    expectExactCliff(makeTerrain(k2To20 + 1), 997);
}

void expectLoneSpikes(const ProceduralTerrain& t, std::size_t expectedCount) {
    ASSERT_EQ(t.spikes().size(), expectedCount);
    for (const TerrainSpike& s : t.spikes()) {
        EXPECT_EQ(s.heightAboveNeighboursM, 250.0F);
        const std::vector<float> n = window(t, s.x - 1, s.y - 1, 3, 3);
        ASSERT_TRUE(bitEqual(n[4], s.heightM));
        float highest = -1e30F;
        for (std::size_t i = 0; i < 9; ++i) {
            if (i == 4) continue;
            highest = std::max(highest, n[i]);
            EXPECT_GE(n[4] - n[i], s.heightAboveNeighboursM)
                << "spike (" << s.x << ", " << s.y << ")";
        }
        // Exactly the known height above the highest neighbour (an exact float difference).
        EXPECT_EQ(n[4] - highest, s.heightAboveNeighboursM);
        // One sample wide: no neighbour stands out of its own ring (the spike left out)
        // the way the spike does.
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
            for (std::int64_t dx = -1; dx <= 1; ++dx) {
                if (dx == 0 && dy == 0) continue;
                const std::vector<float> ring = window(t, s.x + dx - 1, s.y + dy - 1, 3, 3);
                float ringHighest = -1e30F;
                for (std::int64_t j = 0; j < 3; ++j) {
                    for (std::int64_t i = 0; i < 3; ++i) {
                        const bool centre = i == 1 && j == 1;
                        const bool spike = s.x + dx - 1 + i == s.x && s.y + dy - 1 + j == s.y;
                        if (!centre && !spike)
                            ringHighest =
                                std::max(ringHighest, ring[static_cast<std::size_t>(j * 3 + i)]);
                    }
                }
                EXPECT_LT(ring[4] - ringHighest, 0.5F * s.heightAboveNeighboursM);
            }
        }
    }
}

TEST(ProceduralTerrain, SpikesAreOneSampleWideAndStandTheirHeightAboveAllNeighbours) {
    expectLoneSpikes(makeTerrain(), 8);
    expectLoneSpikes(makeTerrain(1025, 42), 8);
    expectLoneSpikes(makeTerrain(k2To20 + 1), 8);
    expectLoneSpikes(makeTerrain(2 * k2To32 + 1), 8);
}

TEST(ProceduralTerrain, LakeIsExactlyFlatAndLarge) {
    for (const std::uint64_t seed : {1ULL, 2ULL, 3ULL}) {
        const ProceduralTerrain t = makeTerrain(1025, seed);
        ASSERT_TRUE(t.lake().has_value()) << "seed " << seed;
        const TerrainLake& lake = *t.lake();
        const SampleBox& b = lake.bounds;
        const std::vector<float> w =
            window(t, b.minX, b.minY, b.maxX - b.minX + 1, b.maxY - b.minY + 1);
        std::int64_t lakeSamples = 0;
        for (std::int64_t y = b.minY; y <= b.maxY; ++y) {
            for (std::int64_t x = b.minX; x <= b.maxX; ++x) {
                if (!t.isLake(x, y)) continue;
                ++lakeSamples;
                const float h = w[static_cast<std::size_t>((y - b.minY) * (b.maxX - b.minX + 1) +
                                                           (x - b.minX))];
                ASSERT_TRUE(bitEqual(h, lake.levelM)) << "(" << x << ", " << y << ") " << h;
            }
        }
        // Radius 0.08 of 1024 samples with a ±30 % shoreline: at least the inner disc.
        EXPECT_GT(lakeSamples, 10000) << "seed " << seed;
        // Nothing outside the bounds is lake.
        EXPECT_FALSE(t.isLake(b.minX - 1, b.minY - 1));
    }
}

TEST(ProceduralTerrain, LakeIsFlatOnAMillionSampleDem) {
    const ProceduralTerrain t = makeTerrain(k2To20 + 1);
    ASSERT_TRUE(t.lake().has_value());
    const TerrainLake& lake = *t.lake();
    // A 400 × 400 window at the centre lies well inside the inner disc (radius ~58,000).
    const auto cx = static_cast<std::int64_t>(lake.centreX);
    const auto cy = static_cast<std::int64_t>(lake.centreY);
    const std::vector<float> w = window(t, cx - 200, cy - 200, 400, 400, 2);
    for (const float h : w) ASSERT_TRUE(bitEqual(h, lake.levelM));
    EXPECT_TRUE(t.isLake(cx, cy));
}

TEST(ProceduralTerrain, PlateauTopsAreFlatAndStandAboveTheirSurroundings) {
    const ProceduralTerrain t = makeTerrain();
    ASSERT_EQ(t.plateaus().size(), 3U);
    for (std::size_t i = 0; i < t.plateaus().size(); ++i) {
        const TerrainPlateau& p = t.plateaus()[i];
        const SampleBox& b = p.topBounds;
        std::int64_t top = 0;
        for (std::int64_t y = b.minY; y <= b.maxY; ++y) {
            for (std::int64_t x = b.minX; x <= b.maxX; ++x) {
                if (t.plateauTopAt(x, y) != i) continue;
                ++top;
                ASSERT_TRUE(bitEqual(t.sample(x, y), p.topHeightM));
            }
        }
        EXPECT_GT(top, 3000);  // radius 0.045 · 1024 ≈ 46 samples, ±25 %
        EXPECT_GE(p.topHeightM, 0.0F);
        EXPECT_LE(p.topHeightM, t.maxHeightBoundM());
        // The centre is on top, and far outside the mesa is not.
        EXPECT_EQ(t.plateauTopAt(std::llround(p.centreX), std::llround(p.centreY)), i);
        EXPECT_FALSE(t.plateauTopAt(b.maxX + 1, b.maxY + 1).has_value());
    }
}

TEST(ProceduralTerrain, HeightsAreFiniteAndBoundedOnHugeDems) {
    for (const std::int64_t side :
         {k2To20 + 1, 2 * k2To32 + 1, ProceduralTerrain::kMaxSideSamples}) {
        const ProceduralTerrain t = makeTerrain(side, 5);
        std::mt19937_64 rng(side);
        for (int i = 0; i < 12; ++i) {
            const std::int64_t x0 = std::uniform_int_distribution<std::int64_t>(0, side - 48)(rng);
            const std::int64_t y0 = std::uniform_int_distribution<std::int64_t>(0, side - 48)(rng);
            for (const float h : window(t, x0, y0, 48, 48)) {
                ASSERT_TRUE(std::isfinite(h));
                ASSERT_GE(h, 0.0F);
                ASSERT_LE(h, t.maxHeightBoundM());
            }
        }
    }
}

TEST(ProceduralTerrain, LargerDemsShowTheSameLandscape) {
    const ProceduralTerrain small = makeTerrain(1025);
    const ProceduralTerrain large = makeTerrain(k2To20 + 1);
    const double ratio = 1024.0;  // (large − 1) / (small − 1)
    ASSERT_TRUE(small.lake() && large.lake());
    EXPECT_NEAR(large.lake()->centreX / ratio, small.lake()->centreX, 1e-6);
    EXPECT_NEAR(large.lake()->centreY / ratio, small.lake()->centreY, 1e-6);
    EXPECT_NEAR(static_cast<double>(large.cliffColumn(0)) / ratio,
                static_cast<double>(small.cliffColumn(0)), 1.0);
    ASSERT_EQ(large.plateaus().size(), small.plateaus().size());
    // The relief agrees up to the octaves only the larger DEM has.
    double worst = 0.0;
    for (std::int64_t j = 1; j < 1024; j += 97) {
        for (std::int64_t i = 1; i < 1024; i += 89) {
            if (std::abs(i - small.cliffColumn(j)) < 3) continue;
            const double a = small.sample(i, j);
            const double b = large.sample(i * 1024, j * 1024);
            worst = std::max(worst, std::abs(a - b));
        }
    }
    EXPECT_LT(worst, 200.0);
}

TEST(ProceduralTerrain, GeoreferenceOfAWindow) {
    const ProceduralTerrain t = makeTerrain();
    const Georeference g = t.windowGeoreference(100, 200, 32610);
    EXPECT_EQ(g.originX, 3000.0);
    EXPECT_EQ(g.originY, (1025.0 - 200.0) * 30.0);
    EXPECT_EQ(g.pixelSizeX, 30.0);
    EXPECT_EQ(g.pixelSizeY, 30.0);
    EXPECT_EQ(g.epsg, 32610);
}

TEST(ProceduralTerrain, BadParametersAreErrorsNamingTheParameter) {
    ProceduralTerrainParameters p;
    p.widthSamples = 10;
    Result<ProceduralTerrain> small = ProceduralTerrain::create(p);
    ASSERT_FALSE(small.ok());
    EXPECT_NE(small.error().message.find("widthSamples"), std::string::npos);

    p = {};
    p.sampleSpacingM = -1.0;
    ASSERT_FALSE(ProceduralTerrain::create(p).ok());

    p = {};
    p.mountainHeightM = 9000.0;
    Result<ProceduralTerrain> tall = ProceduralTerrain::create(p);
    ASSERT_FALSE(tall.ok());
    EXPECT_NE(tall.error().message.find("8192"), std::string::npos);

    p = {};
    p.heightSamples = ProceduralTerrain::kMaxSideSamples + 1;
    EXPECT_FALSE(ProceduralTerrain::create(p).ok());
}

TEST(ProceduralTerrain, FeaturesCanBeTurnedOff) {
    ProceduralTerrainParameters p;
    p.cliffHeightM = 0.0;
    p.lakeRadius = 0.0;
    p.plateauCount = 0;
    p.spikeCount = 0;
    Result<ProceduralTerrain> t = ProceduralTerrain::create(p);
    ASSERT_TRUE(t.ok());
    EXPECT_FALSE(t.value().hasCliff());
    EXPECT_FALSE(t.value().lake().has_value());
    EXPECT_TRUE(t.value().plateaus().empty());
    EXPECT_TRUE(t.value().spikes().empty());
    EXPECT_FALSE(t.value().isLake(512, 512));
}

}  // namespace
}  // namespace terrain::io
