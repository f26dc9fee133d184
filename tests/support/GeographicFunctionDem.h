// GeographicFunctionDem: a geographic (WGS84 longitude/latitude) DEM held by a function of
// latitude and longitude, for globe tests that need a source anywhere on Earth: a cap over a
// pole, a strip across the antimeridian, a whole planet. NaN heights are no-data.
#pragma once

#include "terrain/source/DemReader.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <utility>

namespace terrain::test {

/// A geographic source held by a function of latitude and longitude (degrees); NaN is no-data.
class GeographicFunctionDem final : public io::DemReader {
public:
    using Height = std::function<float(double latitude, double longitude)>;
    GeographicFunctionDem(double west, double north, std::int64_t width, std::int64_t height,
                          double pixelLon, double pixelLat, Height heightAt)
        : m_height(std::move(heightAt)) {
        m_info.path = "geographic-function-dem";
        m_info.readerName = "test";
        m_info.inputs = {m_info.path};
        m_info.width = width;
        m_info.height = height;
        m_info.sampleType = "float32";
        m_info.hasGeoreference = true;
        m_info.georeference = {west,
                               north,
                               pixelLon,
                               pixelLat,
                               io::Georeference::kWgs84Geographic,
                               io::CrsKind::Geographic};
        m_info.noDataValue = -32768.0;
    }
    const io::DemInfo& info() const override { return m_info; }
    /// The raw value it declares as no-data (metadata only: its voids are NaN heights).
    void setNoDataValue(std::optional<double> value) { m_info.noDataValue = value; }
    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        const io::Georeference& g = m_info.georeference;
        for (std::int64_t y = 0; y < rows; ++y)
            for (std::int64_t x = 0; x < width; ++x)
                out[static_cast<std::size_t>(y * width + x)] =
                    m_height(g.originY - (double(y0 + y) + 0.5) * g.pixelSizeY,
                             g.originX + (double(x0 + x) + 0.5) * g.pixelSizeX);
        return {};
    }

private:
    io::DemInfo m_info;
    Height m_height;
};

}  // namespace terrain::test
