// Access to the real DEMs in ../shared/data for tests. Without them a test skips with a
// message; with TERRAIN_REQUIRE_SHARED_DATA=1 (CI) the skip becomes a failure, so CI
// cannot pass by skipping.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace terrain::test {

/// TERRAIN_SHARED_DATA_DIR if set, else <source>/../shared/data.
inline std::filesystem::path sharedDataDir() {
    if (const char* dir = std::getenv("TERRAIN_SHARED_DATA_DIR")) return dir;
    return std::filesystem::path(TERRAIN_SOURCE_DIR) / ".." / "shared" / "data";
}

inline bool sharedDataRequired() {
    const char* value = std::getenv("TERRAIN_REQUIRE_SHARED_DATA");
    return value != nullptr && std::string(value) == "1";
}

}  // namespace terrain::test

/// Declares `variable` = ../shared/data/<fileName>, or skips (fails under
/// TERRAIN_REQUIRE_SHARED_DATA=1) when the file is absent.
#define TERRAIN_SHARED_DATA_OR_SKIP(variable, fileName)                                     \
    const ::std::filesystem::path variable = ::terrain::test::sharedDataDir() / (fileName); \
    if (!::std::filesystem::exists(variable)) {                                             \
        if (::terrain::test::sharedDataRequired())                                          \
            FAIL() << "shared data " << variable                                            \
                   << " is missing and TERRAIN_REQUIRE_SHARED_DATA=1";                      \
        GTEST_SKIP() << "shared data " << variable                                          \
                     << " is absent (../shared not beside the checkout)";                   \
    }
