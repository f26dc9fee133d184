// The "gl" object of every rendering tool's --json summary: which platform, driver and
// version the run had, so figures are never quoted without the renderer behind them.
#pragma once

#include "terrain/gl/GlInfo.h"

#include <nlohmann/json.hpp>

namespace terrain::tools {

nlohmann::json glInfoJson(const gl::GlInfo& info);

}  // namespace terrain::tools
