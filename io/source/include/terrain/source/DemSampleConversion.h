// Raw DEM samples to metres, as DemReader::readWindow promises: no-data and NaN samples
// become quiet NaN, the others raw · scale + offset. One loop shared by every reader.
#pragma once

#include "terrain/source/DemReader.h"

#include <cmath>
#include <concepts>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>

namespace terrain::io::detail {

/// The no-data test in the source's own type: an integer raster matches only an integral
/// no-data value in its range, a float raster compares after rounding the value to the
/// type (GDAL keeps float no-data values as doubles, e.g. -9.9999998e+33 for -1e34f).
template <typename T>
struct NoDataTest {
    bool active = false;
    T value{};

    explicit NoDataTest(std::optional<double> noData) {
        if (!noData || std::isnan(*noData)) return;  // NaN is caught as NaN anyway
        if constexpr (std::floating_point<T>) {
            active = true;
            value = static_cast<T>(*noData);
        } else {
            const double v = *noData;
            if (v != std::floor(v) || v < static_cast<double>(std::numeric_limits<T>::lowest()) ||
                v > static_cast<double>(std::numeric_limits<T>::max()))
                return;
            active = true;
            value = static_cast<T>(v);
        }
    }
    bool operator()(T raw) const { return active && raw == value; }
};

/// out[i] = metres of raw[i]. out may alias raw when T is float (in place).
template <typename T>
void convertDemSamples(const T* raw, std::size_t count, float* out,
                       const VerticalTransform& vertical, std::optional<double> noData) {
    const NoDataTest<T> isNoData(noData);
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    const bool identity = vertical.scale == 1.0 && vertical.offset == 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        const T r = raw[i];
        if constexpr (std::floating_point<T>) {
            if (std::isnan(r)) {
                out[i] = kNaN;
                continue;
            }
        }
        if (isNoData(r)) {
            out[i] = kNaN;
        } else if (identity) {
            out[i] = static_cast<float>(r);
        } else {
            out[i] = static_cast<float>(static_cast<double>(r) * vertical.scale + vertical.offset);
        }
    }
}

/// For sources whose samples are metres already (the procedural terrain and planet): the
/// vertical transform and no-data value the open options set, applied in place.
inline void applyDemOverrides(const DemInfo& info, std::span<float> window) {
    if (info.vertical != VerticalTransform{} || info.noDataValue)
        convertDemSamples(window.data(), window.size(), window.data(), info.vertical,
                          info.noDataValue);
}

}  // namespace terrain::io::detail
