// The GeoTIFF tags and keys this project reads and writes. GeoTIFF 1.1 (OGC 19-008r4):
// §7.3 ModelPixelScale / ModelTiepoint, §7.1 GeoKeyDirectory, §7.4 the keys below.
#pragma once

#include <tiffio.h>

#include <cstdint>

namespace terrain::io::detail {

inline constexpr ttag_t kModelPixelScaleTag = 33550;  // (ScaleX, ScaleY, ScaleZ)
inline constexpr ttag_t kModelTiepointTag = 33922;    // (I, J, K, X, Y, Z) per point
inline constexpr ttag_t kModelTransformationTag = 34264;
inline constexpr ttag_t kGeoKeyDirectoryTag = 34735;  // uint16 header + 4 per key
inline constexpr ttag_t kGeoAsciiParamsTag = 34737;   // '|'-terminated strings

inline constexpr std::uint16_t kGTModelTypeGeoKey = 1024;
inline constexpr std::uint16_t kGTRasterTypeGeoKey = 1025;
inline constexpr std::uint16_t kGTCitationGeoKey = 1026;
inline constexpr std::uint16_t kProjectedCRSGeoKey = 3072;
inline constexpr std::uint16_t kProjLinearUnitsGeoKey = 3076;

inline constexpr std::uint16_t kModelTypeProjected = 1;
inline constexpr std::uint16_t kRasterPixelIsArea = 1;
inline constexpr std::uint16_t kUserDefined = 32767;
inline constexpr std::uint16_t kLinearMetre = 9001;  // EPSG unit code

}  // namespace terrain::io::detail
