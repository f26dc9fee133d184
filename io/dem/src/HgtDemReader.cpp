// SRTM .hgt reader: a headerless square of big-endian int16 samples, north row first,
// whose size says the resolution (1201² = 3", 3601² = 1") and whose file name says the
// place (N57E011: the south-west corner at 57° N, 11° E). Windows are read with pread, a
// row segment at a time, so a reader holds no more than the window.
#include "DemReaderFactories.h"
#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemSampleConversion.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

namespace terrain::io::detail {

namespace {

constexpr std::int16_t kHgtVoid = -32768;
constexpr std::int64_t kSrtm3Side = 1201;
constexpr std::int64_t kSrtm1Side = 3601;

struct HgtTileCorner {
    int latitude = 0;   // of the south edge, degrees
    int longitude = 0;  // of the west edge, degrees
};

// "N57E011" at the start of the file name (case-insensitive, so "n57e011.hgt" and
// "N57E011.SRTMGL1.hgt" both work); nullopt when the name says no place.
std::optional<HgtTileCorner> parseHgtTileName(const std::string& fileName) {
    if (fileName.size() < 7) return std::nullopt;
    const auto digits = [&](std::size_t from, std::size_t count) -> std::optional<int> {
        int value = 0;
        for (std::size_t i = from; i < from + count; ++i) {
            if (std::isdigit(static_cast<unsigned char>(fileName[i])) == 0) return std::nullopt;
            value = value * 10 + (fileName[i] - '0');
        }
        return value;
    };
    const char ns = static_cast<char>(std::toupper(static_cast<unsigned char>(fileName[0])));
    const char ew = static_cast<char>(std::toupper(static_cast<unsigned char>(fileName[3])));
    const std::optional<int> lat = digits(1, 2);
    const std::optional<int> lon = digits(4, 3);
    if ((ns != 'N' && ns != 'S') || (ew != 'E' && ew != 'W') || !lat || !lon) return std::nullopt;
    if (*lat > 89 || *lon > 180 || (ew == 'E' && *lon > 179)) return std::nullopt;
    return HgtTileCorner{ns == 'N' ? *lat : -*lat, ew == 'E' ? *lon : -*lon};
}

class FileDescriptor {
public:
    explicit FileDescriptor(int fd) : m_fd(fd) {}
    ~FileDescriptor() {
        if (m_fd >= 0) ::close(m_fd);
    }
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    int get() const { return m_fd; }

private:
    int m_fd = -1;
};

class HgtDemReader final : public DemReader {
public:
    HgtDemReader(DemInfo info, int fd) : m_info(std::move(info)), m_file(fd) {}

    const DemInfo& info() const override { return m_info; }

    Status readWindow(std::int64_t x0, std::int64_t y0, std::int64_t width, std::int64_t rows,
                      std::span<float> out) override {
        assertDemWindow(m_info, x0, y0, width, rows, out);
        m_row.resize(static_cast<std::size_t>(width));
        const std::size_t bytes = m_row.size() * sizeof(std::int16_t);
        for (std::int64_t r = 0; r < rows; ++r) {
            const auto offset =
                static_cast<off_t>(((y0 + r) * m_info.width + x0) * std::int64_t{2});
            std::size_t done = 0;
            auto* dst = reinterpret_cast<char*>(m_row.data());
            while (done < bytes) {
                const ssize_t n = ::pread(m_file.get(), dst + done, bytes - done,
                                          offset + static_cast<off_t>(done));
                if (n < 0 && errno == EINTR) continue;
                if (n < 0)
                    return Error{fmt::format("{}: read failed at byte {}: {}", m_info.path,
                                             offset + static_cast<off_t>(done),
                                             std::strerror(errno))};
                if (n == 0)
                    return Error{fmt::format("{}: truncated: row {} ends past the end of the file",
                                             m_info.path, y0 + r)};
                done += static_cast<std::size_t>(n);
            }
            for (std::int16_t& v : m_row) {  // big-endian on disk
                const auto u = static_cast<std::uint16_t>(v);
                v = static_cast<std::int16_t>(static_cast<std::uint16_t>((u >> 8U) | (u << 8U)));
            }
            convertDemSamples(m_row.data(), m_row.size(),
                              out.data() + static_cast<std::size_t>(r * width), m_info.vertical,
                              m_info.noDataValue);
        }
        return {};
    }

private:
    DemInfo m_info;
    FileDescriptor m_file;
    std::vector<std::int16_t> m_row;
};

}  // namespace

DemReaderResult openHgtDem(const std::string& path, const DemOpenOptions& options) {
    const Result<std::uint64_t> size = checkDemInputFile(path);
    if (!size) return size.error();
    std::int64_t side = 0;
    for (const std::int64_t candidate : {kSrtm3Side, kSrtm1Side})
        if (size.value() == static_cast<std::uint64_t>(candidate * candidate * 2)) side = candidate;
    if (side == 0)
        return Error{fmt::format(
            "{}: {} bytes is not an SRTM .hgt size ({} bytes for 1201² samples, {} for 3601²)",
            path, size.value(), kSrtm3Side * kSrtm3Side * 2, kSrtm1Side * kSrtm1Side * 2)};

    DemInfo info;
    info.path = path;
    info.readerName = "hgt";
    info.inputs = {path};
    info.width = side;
    info.height = side;
    info.sampleType = "int16";
    info.noDataValue = kHgtVoid;
    info.georeference.crsKind = CrsKind::Unknown;
    const std::string name = std::filesystem::path(path).filename().string();
    if (const std::optional<HgtTileCorner> corner = parseHgtTileName(name)) {
        // Samples sit on the lattice including both edges (pixel-is-point); the area
        // convention puts the corner half a step outside the tile.
        const double step = 1.0 / static_cast<double>(side - 1);
        Georeference& geo = info.georeference;
        geo.pixelSizeX = geo.pixelSizeY = step;
        geo.originX = corner->longitude - 0.5 * step;
        geo.originY = corner->latitude + 1 + 0.5 * step;
        geo.crsKind = CrsKind::Geographic;
        geo.epsg = Georeference::kWgs84Geographic;
        info.hasGeoreference = true;
    }
    if (Status s = applyDemOpenOptions(info, options); !s) return s.error();

    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return Error{fmt::format("{}: cannot open: {}", path, std::strerror(errno))};
    return std::unique_ptr<DemReader>(std::make_unique<HgtDemReader>(std::move(info), fd));
}

}  // namespace terrain::io::detail
