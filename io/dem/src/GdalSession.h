// GDAL plumbing shared by the GDAL readers and the CRS lookups: driver registration once
// per process, GDAL's messages captured for our Error texts (instead of GDAL's default
// print to stderr), and a dataset handle that closes itself.
#pragma once

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <memory>
#include <string>

namespace terrain::io::detail {

/// GDALAllRegister, once per process. Any thread.
void ensureGdalRegistered();

/// While alive, GDAL errors and warnings raised on this thread go to this object, not to
/// stderr (CPLPushErrorHandlerEx: the handler stack is per thread). Scope it around
/// every GDAL call whose failure we report.
class GdalErrorCapture {
public:
    GdalErrorCapture();
    ~GdalErrorCapture();
    GdalErrorCapture(const GdalErrorCapture&) = delete;
    GdalErrorCapture& operator=(const GdalErrorCapture&) = delete;

    /// GDAL's first failure message since construction, else `fallback`.
    std::string message(const std::string& fallback) const;

private:
    static void CPL_STDCALL handle(CPLErr level, CPLErrorNum number, const char* text);
    std::string m_firstError;
};

/// The CRS as one-line OGC WKT2 (2019), which keeps names WKT1 loses (e.g. a
/// conversion's "UTM zone 5N"); empty if GDAL cannot export it.
std::string wktOf(const OGRSpatialReference& srs);

struct GdalDatasetCloser {
    void operator()(GDALDataset* dataset) const { GDALClose(GDALDataset::ToHandle(dataset)); }
};
using GdalDataset = std::unique_ptr<GDALDataset, GdalDatasetCloser>;

}  // namespace terrain::io::detail
