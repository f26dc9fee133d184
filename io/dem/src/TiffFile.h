// TiffFile: a libtiff handle that closes itself and keeps libtiff's first error message
// (per handle, through TIFFOpenExt's handlers, instead of libtiff's global stderr print).
#pragma once

#include <tiffio.h>

#include <filesystem>
#include <string>

namespace terrain::io::detail {

class TiffFile {
public:
    /// mode as TIFFOpen: "r", "w" (classic TIFF) or "w8" (BigTIFF).
    TiffFile(const std::filesystem::path& path, const char* mode);
    ~TiffFile();
    // libtiff holds the address of m_error: neither copyable nor movable.
    TiffFile(const TiffFile&) = delete;
    TiffFile& operator=(const TiffFile&) = delete;

    TIFF* get() const { return m_tiff; }
    explicit operator bool() const { return m_tiff != nullptr; }

    /// Flushes and closes; false if libtiff reported an error at any time.
    bool close();

    /// libtiff's first error, "module: message", or a fallback naming what failed.
    std::string error(const char* fallback) const;

private:
    TIFF* m_tiff = nullptr;
    std::string m_error;
};

}  // namespace terrain::io::detail
