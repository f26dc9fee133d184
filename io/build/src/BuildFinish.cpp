#include "BuildFinish.h"

#include "BuildOutput.h"

#include <fmt/format.h>

namespace terrain::io::detail {

void describeSources(PyramidManifest& m, std::span<DemReader* const> readers) {
    const DemInfo& first = readers.front()->info();
    m.georeference = first.georeference;
    m.vertical = first.vertical;
    m.noData.sourceValue = first.noDataValue;
    for (DemReader* reader : readers)
        for (const std::string& input : reader->info().inputs) m.source.inputs.push_back(input);
    m.source.reader = first.readerName;
    m.source.sampleType = first.sampleType;
    m.source.band = first.band;
    m.source.bandCount = first.bandCount;
    m.source.rowsFlipped = first.rowsFlipped;
    m.source.columnsFlipped = first.columnsFlipped;
    m.build.tool = "terrain-build";
    m.build.version = TERRAIN_VERSION;
}

Status checkCoverage(const std::string& path, std::int64_t samples, std::int64_t validSamples,
                     std::vector<std::string>& warnings) {
    if (validSamples <= 0)
        return Error{fmt::format(
            "{}: no valid sample: all {} samples are no-data or NaN (a wrong band, or a wrong "
            "--nodata?)",
            path, samples)};
    if (samples > 0 && 2 * validSamples < samples)
        warnings.push_back(fmt::format(
            "{}: {:.1f} % of its {} samples are no-data; the pyramid fills them from their "
            "neighbours",
            path,
            100.0 * static_cast<double>(samples - validSamples) / static_cast<double>(samples),
            samples));
    return {};
}

Result<PyramidBuildSummary> finishBuild(PyramidManifest manifest, BuildTotals totals,
                                        const std::filesystem::path& folder) {
    PyramidBuildSummary summary;
    manifest.build.seconds = totals.seconds;
    if (Status written = writeManifest(folder, manifest); !written) return written.error();
    summary.manifest = std::move(manifest);
    summary.patches = totals.patches;
    summary.phases = totals.phases;
    summary.seconds = totals.seconds;
    summary.warnings = std::move(totals.warnings);
    summary.bytes = folderBytes(folder);
    return summary;
}

}  // namespace terrain::io::detail
