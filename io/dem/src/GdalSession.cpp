// GDAL registration and error capture (see GdalSession.h).
#include "GdalSession.h"

#include <cpl_conv.h>
#include <cpl_error.h>

#include <mutex>
#include <string>

namespace terrain::io::detail {

void ensureGdalRegistered() {
    static std::once_flag once;
    std::call_once(once, [] {
        // Drivers that crash on a damaged file and read no format a DEM comes in, skipped
        // (GDAL_SKIP, added to the user's): NDF, Landsat's NLAPS imagery, dereferences a
        // bad pointer in GDAL 3.6's Open on a 200-byte header (found by fuzz-dem-netcdf;
        // tests/fuzz/dem-netcdf/ndf-header-crashes-gdal-3.6.nc).
        const std::string skip = CPLGetConfigOption("GDAL_SKIP", "");
        CPLSetConfigOption("GDAL_SKIP", (skip.empty() ? "NDF" : skip + " NDF").c_str());
        GDALAllRegister();
    });
}

GdalErrorCapture::GdalErrorCapture() { CPLPushErrorHandlerEx(&GdalErrorCapture::handle, this); }

GdalErrorCapture::~GdalErrorCapture() { CPLPopErrorHandler(); }

void CPL_STDCALL GdalErrorCapture::handle(CPLErr level, CPLErrorNum, const char* text) {
    // Warnings (e.g. the netCDF driver's notes on axis names) are dropped: they are not
    // about the caller's data being wrong.
    if (level < CE_Failure || text == nullptr) return;
    auto* self = static_cast<GdalErrorCapture*>(CPLGetErrorHandlerUserData());
    if (self != nullptr && self->m_firstError.empty()) self->m_firstError = text;
}

std::string wktOf(const OGRSpatialReference& srs) {
    GdalErrorCapture errors;
    const char* const options[] = {"FORMAT=WKT2_2019", "MULTILINE=NO", nullptr};
    char* text = nullptr;
    std::string wkt;
    if (srs.exportToWkt(&text, options) == OGRERR_NONE && text != nullptr) wkt = text;
    CPLFree(text);
    return wkt;
}

std::string GdalErrorCapture::message(const std::string& fallback) const {
    return m_firstError.empty() ? fallback : m_firstError;
}

}  // namespace terrain::io::detail
