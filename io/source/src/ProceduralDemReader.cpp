// The procedural terrain (ProceduralTerrain.h) as a DEM input: "procedural:" followed by
// optional comma-separated keys size=, width=, height=, seed=, spacing= (metres).
#include "ProceduralReaders.h"
#include "terrain/source/DemSampleConversion.h"

#include "terrain/source/KeyValueSpec.h"
#include "terrain/source/ProceduralTerrain.h"

#include <fmt/format.h>

#include <cmath>
#include <string_view>

namespace terrain::io::detail {

namespace {

constexpr std::string_view kProceduralPrefix = "procedural:";
constexpr unsigned kFillThreads = 2;

Result<ProceduralTerrainParameters> parseProceduralSpec(const std::string& spec) {
    ProceduralTerrainParameters parameters;
    const Status parsed = parseKeyValueSpec(
        spec, kProceduralPrefix, "size, width, height, seed, spacing",
        [&](std::string_view key, std::string_view value) {
            bool ok = true;
            if (key == "size") {
                std::int64_t side = 0;
                ok = parseSpecNumber(value, side);
                parameters.widthSamples = parameters.heightSamples = side;
            } else if (key == "width") {
                ok = parseSpecNumber(value, parameters.widthSamples);
            } else if (key == "height") {
                ok = parseSpecNumber(value, parameters.heightSamples);
            } else if (key == "seed") {
                ok = parseSpecNumber(value, parameters.seed);
            } else if (key == "spacing") {
                ok = parseSpecNumber(value, parameters.sampleSpacingM) &&
                     std::isfinite(parameters.sampleSpacingM) && parameters.sampleSpacingM > 0.0;
            } else {
                return SpecKey::Unknown;
            }
            return ok ? SpecKey::Taken : SpecKey::BadValue;
        });
    if (!parsed) return parsed.error();
    return parameters;
}

class ProceduralDemReader final : public DemReader {
public:
    ProceduralDemReader(DemInfo info, ProceduralTerrain terrain)
        : m_info(std::move(info)), m_terrain(std::move(terrain)) {}

    const DemInfo& info() const override { return m_info; }

    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        assertDemWindow(m_info, x0, y0, width, rows, out);
        const std::span<float> window = out.first(static_cast<std::size_t>(width * rows));
        m_terrain.fillWindow(x0, y0, width, rows, window, kFillThreads);
        applyDemOverrides(m_info, window);
        return {};
    }

private:
    DemInfo m_info;
    ProceduralTerrain m_terrain;
};

}  // namespace

Result<std::unique_ptr<DemReader>> openProceduralTerrainDem(const std::string& spec,
                                                            const DemInfoAdjustment& adjust) {
    Result<ProceduralTerrainParameters> parameters = parseProceduralSpec(spec);
    if (!parameters) return parameters.error();
    Result<ProceduralTerrain> terrain = ProceduralTerrain::create(parameters.value());
    if (!terrain) return Error{fmt::format("{}: {}", spec, terrain.error().message)};

    DemInfo info;
    info.path = spec;
    info.readerName = "procedural";
    info.inputs = {spec};
    info.width = terrain.value().width();
    info.height = terrain.value().height();
    info.sampleType = "float32";
    info.hasGeoreference = true;
    info.georeference = terrain.value().windowGeoreference(0, 0);
    if (adjust) {
        if (Status s = adjust(info); !s) return s.error();
    }
    return std::unique_ptr<DemReader>(
        std::make_unique<ProceduralDemReader>(std::move(info), std::move(terrain).value()));
}

}  // namespace terrain::io::detail
