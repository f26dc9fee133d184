// The procedural terrain (ProceduralTerrain.h) as a DEM input: "procedural:" followed by
// optional comma-separated keys size=, width=, height=, seed=, spacing= (metres).
#include "DemReaderFactories.h"
#include "DemSampleConversion.h"

#include "terrain/io/ProceduralTerrain.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <string_view>

namespace terrain::io::detail {

namespace {

constexpr std::string_view kPrefix = "procedural:";
constexpr unsigned kFillThreads = 2;

template <typename T>
bool parseNumber(std::string_view text, T& value) {
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size();
}

Result<ProceduralTerrainParameters> parseProceduralSpec(const std::string& spec) {
    ProceduralTerrainParameters parameters;
    std::string_view rest = std::string_view(spec).substr(kPrefix.size());
    while (!rest.empty()) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
        if (item.empty()) continue;
        const std::size_t equals = item.find('=');
        const std::string_view key = item.substr(0, equals);
        const std::string_view value =
            equals == std::string_view::npos ? std::string_view() : item.substr(equals + 1);
        const auto bad = [&](std::string_view what) {
            return Error{fmt::format("{}: {} '{}' (keys: size, width, height, seed, spacing)", spec,
                                     what, item)};
        };
        if (equals == std::string_view::npos) return bad("expected key=value, got");
        bool ok = true;
        if (key == "size") {
            std::int64_t side = 0;
            ok = parseNumber(value, side);
            parameters.widthSamples = parameters.heightSamples = side;
        } else if (key == "width") {
            ok = parseNumber(value, parameters.widthSamples);
        } else if (key == "height") {
            ok = parseNumber(value, parameters.heightSamples);
        } else if (key == "seed") {
            ok = parseNumber(value, parameters.seed);
        } else if (key == "spacing") {
            ok = parseNumber(value, parameters.sampleSpacingM) &&
                 std::isfinite(parameters.sampleSpacingM) && parameters.sampleSpacingM > 0.0;
        } else {
            return bad("unknown key in");
        }
        if (!ok) return bad("bad value in");
    }
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
        // Heights are metres already; overrides from the options still apply.
        if (m_info.vertical != VerticalTransform{} || m_info.noDataValue)
            convertDemSamples(window.data(), window.size(), window.data(), m_info.vertical,
                              m_info.noDataValue);
        return {};
    }

private:
    DemInfo m_info;
    ProceduralTerrain m_terrain;
};

}  // namespace

DemReaderResult openProceduralDem(const std::string& spec, const DemOpenOptions& options) {
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
    if (Status s = applyDemOpenOptions(info, options); !s) return s.error();
    return std::unique_ptr<DemReader>(
        std::make_unique<ProceduralDemReader>(std::move(info), std::move(terrain).value()));
}

}  // namespace terrain::io::detail
