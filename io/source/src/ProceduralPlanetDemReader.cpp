// The procedural planet (ProceduralPlanet.h) as a geographic DEM input, evaluated window by
// window: "planet:" followed by optional comma-separated keys seed=, level= (the sample
// spacing: 90° / (2^level · 128), the face grid's at the equator; default 12, 2^21 + 1 ×
// 2^20 + 1 samples for the whole planet) and west=, south=, east=, north= (degrees; default
// the whole planet). Sample (i, j) is at longitude west + i·d, latitude north − j·d; the box's
// east and south edges are rounded to that grid.
#include "ProceduralReaders.h"
#include "terrain/source/DemSampleConversion.h"

#include "terrain/source/KeyValueSpec.h"
#include "terrain/source/ProceduralPlanet.h"

#include <fmt/format.h>

#include <cmath>
#include <string_view>

namespace terrain::io::detail {

namespace {

constexpr std::string_view kPlanetPrefix = "planet:";
constexpr int kDefaultPlanetLevel = 12;
constexpr int kMaxPlanetLevel = 16;  // 2^25 samples around the equator, 1.2 m apart

struct PlanetDemSpec {
    ProceduralPlanetParameters planet;
    int level = kDefaultPlanetLevel;
    double west = -180.0, south = -90.0, east = 180.0, north = 90.0;
};

Result<PlanetDemSpec> parsePlanetSpec(const std::string& spec) {
    PlanetDemSpec parsed;
    const Status read =
        parseKeyValueSpec(spec, kPlanetPrefix, "seed, level, west, south, east, north",
                          [&](std::string_view key, std::string_view value) {
                              bool ok = true;
                              if (key == "seed")
                                  ok = parseSpecNumber(value, parsed.planet.seed);
                              else if (key == "level")
                                  ok = parseSpecNumber(value, parsed.level) && parsed.level >= 0 &&
                                       parsed.level <= kMaxPlanetLevel;
                              else if (key == "west")
                                  ok = parseSpecNumber(value, parsed.west);
                              else if (key == "south")
                                  ok = parseSpecNumber(value, parsed.south);
                              else if (key == "east")
                                  ok = parseSpecNumber(value, parsed.east);
                              else if (key == "north")
                                  ok = parseSpecNumber(value, parsed.north);
                              else
                                  return SpecKey::Unknown;
                              return ok ? SpecKey::Taken : SpecKey::BadValue;
                          });
    if (!read) return read.error();
    if (!(parsed.west >= -180.0 && parsed.west < parsed.east && parsed.east <= 180.0 &&
          parsed.south >= -90.0 && parsed.south < parsed.north && parsed.north <= 90.0))
        return Error{
            fmt::format("{}: the box west {} south {} east {} north {} must have "
                        "-180 ≤ west < east ≤ 180 and -90 ≤ south < north ≤ 90",
                        spec, parsed.west, parsed.south, parsed.east, parsed.north)};
    return parsed;
}

class ProceduralPlanetDemReader final : public DemReader {
public:
    ProceduralPlanetDemReader(DemInfo info, ProceduralPlanet planet, double west, double north,
                              double spacingDeg)
        : m_info(std::move(info)),
          m_planet(planet),
          m_west(west),
          m_north(north),
          m_spacing(spacingDeg) {}

    const DemInfo& info() const override { return m_info; }

    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        assertDemWindow(m_info, x0, y0, width, rows, out);
        for (std::int64_t j = 0; j < rows; ++j) {
            const double latitude = m_north - static_cast<double>(y0 + j) * m_spacing;
            for (std::int64_t i = 0; i < width; ++i) {
                const double longitude = m_west + static_cast<double>(x0 + i) * m_spacing;
                out[static_cast<std::size_t>(j * width + i)] =
                    static_cast<float>(m_planet.heightAtDegrees(latitude, longitude));
            }
        }
        applyDemOverrides(m_info, out.first(static_cast<std::size_t>(width * rows)));
        return {};
    }

private:
    DemInfo m_info;
    ProceduralPlanet m_planet;
    double m_west, m_north, m_spacing;
};

}  // namespace

Result<std::unique_ptr<DemReader>> openProceduralPlanetDem(const std::string& spec,
                                                           const DemInfoAdjustment& adjust) {
    Result<PlanetDemSpec> parsed = parsePlanetSpec(spec);
    if (!parsed) return parsed.error();
    const PlanetDemSpec& p = parsed.value();
    const double spacing = 90.0 / std::ldexp(128.0, p.level);
    DemInfo info;
    info.path = spec;
    info.readerName = "planet";
    info.inputs = {spec};
    info.width = std::llround((p.east - p.west) / spacing) + 1;
    info.height = std::llround((p.north - p.south) / spacing) + 1;
    info.sampleType = "float32";
    info.hasGeoreference = true;
    info.georeference = Georeference{.originX = p.west - 0.5 * spacing,
                                     .originY = p.north + 0.5 * spacing,
                                     .pixelSizeX = spacing,
                                     .pixelSizeY = spacing,
                                     .epsg = Georeference::kWgs84Geographic,
                                     .crsKind = CrsKind::Geographic};
    if (adjust) {
        if (Status s = adjust(info); !s) return s.error();
    }
    return std::unique_ptr<DemReader>(std::make_unique<ProceduralPlanetDemReader>(
        std::move(info), ProceduralPlanet::create(p.planet), p.west, p.north, spacing));
}

}  // namespace terrain::io::detail
