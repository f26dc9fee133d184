// The built-in procedural sources as DEMs: "procedural:size=…,seed=…,spacing=…" (the
// procedural terrain, ProceduralTerrain.h) and "planet:seed=…,level=…,west=…,…" (a window of
// the procedural planet, geographic: ProceduralPlanet.h). openDem opens them too, with the
// command line's overrides; tests and programs that need no file reader open them here.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/source/DemReader.h"

#include <functional>
#include <memory>
#include <string>

namespace terrain::io {

/// Whether `input` names a built-in procedural source ("procedural:…" or "planet:…").
bool isProceduralDemName(const std::string& input);

/// Applied to the DemInfo a procedural source describes before its reader is made (openDem's
/// overrides), so the reader converts samples with the final vertical transform.
using DemInfoAdjustment = std::function<Status(DemInfo&)>;

/// Opens a procedural source by its name. Errors start with the name.
Result<std::unique_ptr<DemReader>> openProceduralDem(const std::string& name,
                                                     const DemInfoAdjustment& adjust = {});

}  // namespace terrain::io
