// Checks of one stored patch against itself (what terrain-inspect --verify asks of every
// present patch): finite values, min/max, block errors recomputed, bounds ordered, the
// no-data count and mask. Each failed check is one Problem naming the file and the patch.
#pragma once

#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <optional>
#include <string>
#include <vector>

namespace terrain::inspect {

struct Problem {
    std::string file;                  ///< the shard file (or the pyramid folder)
    std::optional<io::PatchId> patch;  ///< when the problem is one patch's
    std::string message;               ///< "<file>: patch L<l> (x, y): what is wrong"
};

/// "<file>: patch L<l> (x, y): <what>"
Problem patchProblem(const std::string& file, const io::PatchId& id, const std::string& what);

/// Appends a Problem for every check `record` fails. `hasMask`: the pyramid stores V.
void checkPatchContents(const io::PyramidManifest& manifest, bool hasMask,
                        const io::PatchRecord& record, const std::string& file,
                        std::vector<Problem>& problems);

}  // namespace terrain::inspect
