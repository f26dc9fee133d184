// BenchTruth: what terrain-bench measures a pyramid against, on either surface, as one
// AccuracyProbe (docs/accuracy.md): on the plane the pyramid's finest level (or --reference's,
// the lossless build of a lossy pyramid); on the globe the DEMs it was built from (--source,
// the sources' surface along the ellipsoid normal) and, apart, its own finest level (the LOD's
// error alone, FrameAccuracy::lodError), with the globe's reference image. It keeps alive
// what the probe reads.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/AccuracyProbe.h"

#include <memory>
#include <string>
#include <vector>

namespace terrain::tools {

struct BenchTruthSpec {
    std::string pyramid;
    std::string referencePyramid;      ///< the plane's --reference; empty: the pyramid's own
    std::vector<std::string> sources;  ///< the globe's --source
    io::DemOpenOptions sourceOptions;  ///< how the build read them (terrain-build's flags)
    runtime::AccuracyProbeOptions probe;
};

class BenchTruth {
public:
    /// Errors: a flag of the other surface (--source on the plane, --reference on the globe),
    /// a globe without its sources, a source or pyramid that cannot be read, GL.
    static Result<std::unique_ptr<BenchTruth>> open(const io::PyramidManifest& manifest,
                                                    const BenchTruthSpec& spec);
    virtual ~BenchTruth() = default;

    runtime::AccuracyProbe& probe() { return *m_probe; }

protected:
    std::unique_ptr<runtime::AccuracyProbe> m_probe;
};

}  // namespace terrain::tools
