// libtiff handle with per-handle error capture (see TiffFile.h).
#include "TiffFile.h"

#include <cstdarg>
#include <cstdio>

#include <fcntl.h>

namespace terrain::io::detail {

namespace {

int keepFirstError(TIFF*, void* userData, const char* module, const char* format, va_list args) {
    auto* error = static_cast<std::string*>(userData);
    if (error->empty()) {
        char message[1024];
        std::vsnprintf(message, sizeof message, format, args);
        *error = (module != nullptr && module[0] != '\0') ? std::string(module) + ": " + message
                                                          : std::string(message);
    }
    return 1;  // handled: libtiff prints nothing
}

// Unknown tags (the GeoTIFF ones on reading) and similar are no concern of the caller.
int ignoreWarning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

}  // namespace

TiffFile::TiffFile(const std::filesystem::path& path, const char* mode) {
    TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
    TIFFOpenOptionsSetErrorHandlerExtR(options, keepFirstError, &m_error);
    TIFFOpenOptionsSetWarningHandlerExtR(options, ignoreWarning, nullptr);
    m_tiff = TIFFOpenExt(path.c_str(), mode, options);
    TIFFOpenOptionsFree(options);
}

TiffFile::~TiffFile() { close(); }

bool TiffFile::close() {
    if (m_tiff == nullptr) return m_error.empty();
    const bool flushed = TIFFGetMode(m_tiff) == O_RDONLY || TIFFFlush(m_tiff) == 1;
    TIFFClose(m_tiff);
    m_tiff = nullptr;
    return flushed && m_error.empty();
}

std::string TiffFile::error(const char* fallback) const {
    return m_error.empty() ? std::string(fallback) : m_error;
}

}  // namespace terrain::io::detail
