// Fuzz target: the pyramid manifest parser (io::fromJson, the parse behind readManifest
// and every program's first step). A manifest it accepts must describe a layout every
// later step can use: the layout's arithmetic (levels, patches, shards, shard paths) is
// run over it as a reader would.
#include "TinyPyramids.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <algorithm>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    using namespace terrain::fuzz;
    addSeed(tinyPlanarPyramid() / "manifest.json", "planar-manifest.json");
    addSeed(tinyGlobePyramid() / "manifest.json", "globe-manifest.json");
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace terrain;
    const std::string_view json(reinterpret_cast<const char*>(data), size);
    auto manifest = io::fromJson(json, "fuzz/manifest.json");
    if (!manifest) return 0;
    const io::PyramidLayout& layout = manifest.value().layout;
    for (int level = 0; level <= layout.finestLevel(); ++level) {
        const io::PatchId corner{level, layout.patchesX(level) - 1, layout.patchesY(level) - 1};
        for (const io::PatchId& id : {io::PatchId{level, 0, 0}, corner}) {
            fuzz::require(layout.contains(id), "an accepted layout contains its corner patches");
            (void)layout.shardPath(layout.shardOf(id));
        }
    }
    return 0;
}
