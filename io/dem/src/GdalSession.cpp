// GDAL registration and error capture (see GdalSession.h).
#include "GdalSession.h"

#include <cpl_error.h>

#include <mutex>

namespace terrain::io::detail {

void ensureGdalRegistered() {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
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
