// The "gl" object of every rendering tool's --json summary: which platform, driver and
// version the run had, and which driver workarounds were applied, so figures are never
// quoted without the renderer behind them.
#pragma once

#include "terrain/gl/GlContext.h"

#include <nlohmann/json.hpp>

namespace terrain::tools {

nlohmann::json glInfoJson(const gl::GlContext& context);

}  // namespace terrain::tools
