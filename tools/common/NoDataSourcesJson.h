// Each source's no-data in the tools' JSON summaries (terrain-build --json's "filledSamples",
// terrain-inspect --json's "noDataSources"): the manifest's noData.sources, each source's
// declared no-data value (`sourceValue`, null for none; absent where the manifest predates
// it) and its filled samples (`samples`, `overBeneath` of them over the sources beneath).
#pragma once

#include "terrain/pyramid/PyramidManifest.h"

namespace terrain::tools {

template <typename Json>
Json noDataSourcesJson(const io::ManifestNoData& noData) {
    Json sources = Json::array();
    for (const io::ManifestSourceNoData& source : noData.sources) {
        Json entry{{"input", source.input}};
        if (source.sourceValueRecorded)
            entry["sourceValue"] = source.sourceValue ? Json(*source.sourceValue) : Json();
        entry["samples"] = source.samples;
        entry["overBeneath"] = source.overBeneath;
        sources.push_back(std::move(entry));
    }
    return sources;
}

}  // namespace terrain::tools
