// BuildFinish: the steps that end every build, whole or merged from shards, planar or globe
// (docs/pyramid-format.md, "Manifest"): the manifest's fields that come from the sources, the
// check of how much of a source is data, and writing the manifest with the build's totals.
// A source without a valid sample would build a pyramid of nothing, silently: it is
// refused. One mostly of no-data builds, with a warning, since the filled samples are
// guesses from their neighbours and such a file is often the wrong band or the wrong no-data
// value.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/build/PyramidBuilder.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/source/DemReader.h"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace terrain::io::detail {

/// Fills what the manifest says of the sources alike on every surface: the first source's
/// georeference, vertical units, no-data value, reader, sample type, band and flips, every
/// source's inputs, and the build tool.
void describeSources(PyramidManifest& manifest, std::span<DemReader* const> readers);

/// Refuses a source at `path` without a valid sample among its `samples`; adds a warning to
/// `warnings` when more than half of them are no-data.
Status checkCoverage(const std::string& path, std::int64_t samples, std::int64_t validSamples,
                     std::vector<std::string>& warnings);

/// What a finished build hands its summary besides the manifest.
struct BuildTotals {
    std::int64_t patches = 0;
    PyramidBuildPhases phases;
    double seconds = 0.0;  ///< also the manifest's build.seconds
    std::vector<std::string> warnings;
};

/// Writes `manifest` (build.seconds from the totals) into `folder`, where every shard is in
/// place, and returns the build's summary.
Result<PyramidBuildSummary> finishBuild(PyramidManifest manifest, BuildTotals totals,
                                        const std::filesystem::path& folder);

}  // namespace terrain::io::detail
