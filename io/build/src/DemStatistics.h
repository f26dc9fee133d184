// DemStatistics: what a build counts of its source's samples for the manifest (the heights'
// range, the valid and no-data samples). Each sample is counted by one region of a region
// build, so the shards' statistics add up to the whole build's.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

namespace terrain::io::detail {

struct DemStatistics {
    double minHeight = std::numeric_limits<double>::infinity();
    double maxHeight = -std::numeric_limits<double>::infinity();
    std::int64_t validSamples = 0;
    std::int64_t noDataSamples = 0;

    /// Adds another region's samples.
    void add(const DemStatistics& other) {
        minHeight = std::min(minHeight, other.minHeight);
        maxHeight = std::max(maxHeight, other.maxHeight);
        validSamples += other.validSamples;
        noDataSamples += other.noDataSamples;
    }
};

}  // namespace terrain::io::detail
