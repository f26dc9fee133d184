// The two procedural readers' factories (ProceduralDemReader.cpp, ProceduralPlanetDemReader.cpp),
// dispatched by openProceduralDem.
#pragma once

#include "terrain/source/ProceduralDems.h"

namespace terrain::io::detail {

Result<std::unique_ptr<DemReader>> openProceduralTerrainDem(const std::string& spec,
                                                            const DemInfoAdjustment& adjust);
Result<std::unique_ptr<DemReader>> openProceduralPlanetDem(const std::string& spec,
                                                           const DemInfoAdjustment& adjust);

}  // namespace terrain::io::detail
