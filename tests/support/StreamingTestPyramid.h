// StreamingTestPyramid: one small procedural pyramid per test process, built with the real
// builder (513² samples, 33-sample patches, 4 × 4 blocks: 5 levels, 341 patches), for the
// streaming and LOD tests. Removed when the process ends.
#pragma once

#include "TempFolder.h"
#include "terrain/source/ProceduralDems.h"
#include "terrain/source/DemReader.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

namespace terrain::test {

inline const std::filesystem::path& streamingTestPyramid() {
    static const std::unique_ptr<TempFolder> folder = [] {
        auto f = std::make_unique<TempFolder>();
        auto reader = io::openProceduralDem("procedural:size=513,seed=5");
        EXPECT_TRUE(reader) << reader.error().message;
        io::PyramidBuildOptions options;
        options.patchSamples = 33;
        options.blockQuads = 8;
        options.shardPatches = 4;
        auto built = io::buildPyramid(*reader.value(), f->path() / "p.pyramid", options);
        EXPECT_TRUE(built) << built.error().message;
        return f;
    }();
    static const std::filesystem::path path = folder->path() / "p.pyramid";
    return path;
}

/// Its manifest, read once.
inline const io::PyramidManifest& streamingTestManifest() {
    static const io::PyramidManifest manifest = [] {
        auto read = io::readManifest(streamingTestPyramid());
        EXPECT_TRUE(read) << read.error().message;
        return read ? std::move(read).value() : io::PyramidManifest{};
    }();
    return manifest;
}

}  // namespace terrain::test
