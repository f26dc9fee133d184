// Helpers for the DemReader tests: a temporary folder, whole-raster reads in bands,
// statistics of a raster, and the check that random windows agree with a whole read.
#pragma once

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "TempFolder.h"

#include <unistd.h>

namespace terrain::io::test {

namespace fs = std::filesystem;

using TempDir = terrain::test::TempFolder;

inline void writeBytes(const std::string& path, const std::vector<char>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::vector<char> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The whole raster, read in bands of `bandRows` full-width rows (as the builder does).
inline std::vector<float> readAll(DemReader& reader, std::int64_t bandRows = 131) {
    const DemInfo& info = reader.info();
    std::vector<float> all(static_cast<std::size_t>(info.width * info.height));
    for (std::int64_t y = 0; y < info.height; y += bandRows) {
        const std::int64_t rows = std::min(bandRows, info.height - y);
        const Status s =
            reader.readWindow(0, y, info.width, rows,
                              std::span<float>(all.data() + y * info.width,
                                               static_cast<std::size_t>(rows * info.width)));
        EXPECT_TRUE(s.ok()) << s.error().message;
        if (!s.ok()) break;
    }
    return all;
}

struct SampleStats {
    std::size_t nanCount = 0;
    std::size_t zeroCount = 0;
    float min = std::numeric_limits<float>::infinity();
    float max = -std::numeric_limits<float>::infinity();
};

inline SampleStats statsOf(const std::vector<float>& samples) {
    SampleStats s;
    for (const float v : samples) {
        if (std::isnan(v)) {
            ++s.nanCount;
            continue;
        }
        if (v == 0.0F) ++s.zeroCount;
        s.min = std::min(s.min, v);
        s.max = std::max(s.max, v);
    }
    return s;
}

/// Samples that differ (NaN equals NaN).
inline std::size_t countDifferences(const float* a, const float* b, std::size_t n) {
    std::size_t differences = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) ++differences;
    return differences;
}
inline std::size_t countDifferences(const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size()) return std::max(a.size(), b.size());
    return countDifferences(a.data(), b.data(), a.size());
}

/// `count` random windows (some one sample, some touching the edges) equal the same
/// part of `whole`.
inline void expectRandomWindowsMatch(DemReader& reader, const std::vector<float>& whole,
                                     int count = 40, std::uint32_t seed = 12345) {
    const DemInfo& info = reader.info();
    std::mt19937 random(seed);
    const auto uniform = [&](std::int64_t lo, std::int64_t hi) {
        return std::uniform_int_distribution<std::int64_t>(lo, hi)(random);
    };
    std::vector<float> window;
    for (int i = 0; i < count; ++i) {
        std::int64_t w = uniform(1, std::min<std::int64_t>(info.width, 700));
        std::int64_t h = uniform(1, std::min<std::int64_t>(info.height, 700));
        if (i % 7 == 0) w = h = 1;
        std::int64_t x0 = uniform(0, info.width - w);
        std::int64_t y0 = uniform(0, info.height - h);
        if (i % 5 == 1) {  // touch the south-east corner
            x0 = info.width - w;
            y0 = info.height - h;
        }
        window.assign(static_cast<std::size_t>(w * h), -1.0F);
        const Status s = reader.readWindow(x0, y0, w, h, window);
        ASSERT_TRUE(s.ok()) << s.error().message;
        std::size_t differences = 0;
        for (std::int64_t r = 0; r < h; ++r)
            differences +=
                countDifferences(window.data() + r * w, whole.data() + (y0 + r) * info.width + x0,
                                 static_cast<std::size_t>(w));
        EXPECT_EQ(differences, 0U) << "window " << x0 << "," << y0 << " " << w << "×" << h;
    }
}

inline Result<std::unique_ptr<DemReader>> openOne(const std::string& path,
                                                  const DemOpenOptions& options = {}) {
    return openDem(std::vector<std::string>{path}, options);
}

}  // namespace terrain::io::test
