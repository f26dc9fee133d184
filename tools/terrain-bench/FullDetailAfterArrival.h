// FullDetailAfterArrival: how long a view takes to reach full detail when the camera arrives
// there with nothing loaded (docs/globe.md, "Figures"): a fresh LOD at the pose, frames drawn
// as a user would see them, not settled, until no split waits for a tile, no imagery tile the
// view wants is missing, and nothing loads.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Framebuffer.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainSession.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>

namespace terrain::tools {

/// {"frames": N, "seconds": S, "heights": {"frames", "seconds"}, "imagery": {…}} for
/// `pyramid` opened afresh with `options` and drawn from `camera` into `target`, a frame
/// every kArrivalFrameS at the most (FullDetailClock.h) (the heights
/// and the imagery each at the first frame they were at full detail; the imagery's at once
/// without layers); null when full detail is not reached within `limit`. Errors: the pyramid
/// cannot be opened.
Result<nlohmann::json> fullDetailAfterArrival(const std::string& pyramid,
                                              const runtime::TerrainSessionOptions& options,
                                              const runtime::Camera& camera,
                                              gl::Framebuffer& target, std::chrono::seconds limit);

}  // namespace terrain::tools
