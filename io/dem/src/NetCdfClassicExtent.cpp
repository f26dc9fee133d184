// netCDF classic header walk (format: "The NetCDF Classic Format Specification",
// NetCDF Users Guide, Appendix "File Format Specifications"). Only what is needed to find
// the end of the data: dimensions, attributes skipped, variables' shapes and offsets.
#include "NetCdfClassicExtent.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <vector>

namespace terrain::io::detail {

namespace {

constexpr std::uint32_t kTagDimension = 0x0A;
constexpr std::uint32_t kTagVariable = 0x0B;
constexpr std::uint32_t kTagAttribute = 0x0C;
constexpr std::uint64_t kStreaming = 0xFFFFFFFFU;
constexpr std::size_t kMaxHeaderBytes = std::size_t{64} << 20U;  // sanity bound
constexpr std::uint64_t kMaxCount = std::uint64_t{1} << 32U;

// A bounds-checked big-endian cursor over the header bytes.
class HeaderCursor {
public:
    HeaderCursor(const std::vector<unsigned char>& bytes, bool wideCounts)
        : m_bytes(bytes), m_wideCounts(wideCounts) {}

    bool ok() const { return m_ok; }
    void fail() { m_ok = false; }

    std::uint64_t read(std::size_t size) {
        if (!m_ok || size > m_bytes.size() - m_at) {
            m_ok = false;
            return 0;
        }
        std::uint64_t value = 0;
        for (std::size_t i = 0; i < size; ++i) value = (value << 8U) | m_bytes[m_at + i];
        m_at += size;
        return value;
    }
    std::uint64_t u32() { return read(4); }
    /// NON_NEG: 4 bytes, 8 in CDF-5.
    std::uint64_t count() {
        const std::uint64_t value = read(m_wideCounts ? 8 : 4);
        if (value > kMaxCount) m_ok = false;
        return value;
    }
    void skip(std::uint64_t size) {
        const std::uint64_t padded = (size + 3U) & ~std::uint64_t{3};
        if (!m_ok || padded > m_bytes.size() - m_at) {
            m_ok = false;
            return;
        }
        m_at += static_cast<std::size_t>(padded);
    }
    void skipName() { skip(count()); }

private:
    const std::vector<unsigned char>& m_bytes;
    bool m_wideCounts = false;
    std::size_t m_at = 0;
    bool m_ok = true;
};

std::uint64_t typeBytes(std::uint64_t type) {
    switch (type) {
        case 1:
        case 2:
        case 7:
            return 1;  // byte, char, ubyte
        case 3:
        case 8:
            return 2;  // short, ushort
        case 4:
        case 5:
        case 9:
            return 4;  // int, float, uint
        case 6:
        case 10:
        case 11:
            return 8;  // double, int64, uint64
        default:
            return 0;
    }
}

void skipAttributes(HeaderCursor& c) {
    const std::uint64_t tag = c.u32();
    const std::uint64_t n = c.count();
    if (tag == 0 && n == 0) return;  // ABSENT
    if (tag != kTagAttribute) {
        c.fail();
        return;
    }
    for (std::uint64_t i = 0; i < n && c.ok(); ++i) {
        c.skipName();
        const std::uint64_t type = c.u32();
        const std::uint64_t values = c.count();
        c.skip(values * typeBytes(type));
    }
}

}  // namespace

Result<std::optional<std::uint64_t>> netCdfClassicDataEnd(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char magic[4] = {};
    in.read(reinterpret_cast<char*>(magic), 4);
    if (in.gcount() != 4 || magic[0] != 'C' || magic[1] != 'D' || magic[2] != 'F')
        return std::optional<std::uint64_t>{};
    const unsigned version = magic[3];
    if (version != 1 && version != 2 && version != 5) return std::optional<std::uint64_t>{};
    // The header is at the front; read a generous prefix (large headers are rare), but no
    // more than the file holds: a 64 MiB buffer cleared for every small file made each
    // open cost a second under AddressSanitizer (fuzz-dem-netcdf ran at 1 input a second).
    in.seekg(0, std::ios::end);
    const std::streamoff fileBytes = in.tellg();
    in.seekg(4);
    const std::size_t prefix =
        fileBytes > 4 ? std::min(kMaxHeaderBytes, static_cast<std::size_t>(fileBytes - 4))
                      : kMaxHeaderBytes;
    std::vector<unsigned char> header(prefix);
    in.read(reinterpret_cast<char*>(header.data()), static_cast<std::streamsize>(header.size()));
    header.resize(static_cast<std::size_t>(in.gcount()));

    // Everything below that stops the walk is corruption when the whole file was read; a
    // header larger than the prefix read is only unknown.
    const bool wholeFile = fileBytes > 4
                               ? static_cast<std::streamoff>(header.size()) == fileBytes - 4
                               : header.size() < kMaxHeaderBytes;
    const auto corrupt = [&](const char* what) -> Result<std::optional<std::uint64_t>> {
        if (!wholeFile) return std::optional<std::uint64_t>{};
        return Error{fmt::format("{}: corrupt netCDF header: {}", path, what)};
    };
    HeaderCursor c(header, version == 5);
    const std::uint64_t numrecs = version == 5 ? c.read(8) : c.u32();
    std::vector<std::uint64_t> dimensions;
    {
        const std::uint64_t tag = c.u32();
        const std::uint64_t n = c.count();
        if (!(tag == 0 && n == 0)) {
            if (tag != kTagDimension) return corrupt("the dimension list has a wrong tag");
            for (std::uint64_t i = 0; i < n && c.ok(); ++i) {
                c.skipName();
                dimensions.push_back(c.count());
            }
        }
    }
    skipAttributes(c);  // global attributes

    struct Variable {
        bool record = false;
        std::uint64_t bytes = 0;  // of one record for record variables
        std::uint64_t begin = 0;
    };
    std::vector<Variable> variables;
    const std::uint64_t tag = c.u32();
    const std::uint64_t n = c.count();
    if (!(tag == 0 && n == 0)) {
        if (tag != kTagVariable) return corrupt("the variable list has a wrong tag");
        for (std::uint64_t i = 0; i < n && c.ok(); ++i) {
            c.skipName();
            const std::uint64_t rank = c.count();
            Variable v;
            std::uint64_t elements = 1;
            for (std::uint64_t d = 0; d < rank && c.ok(); ++d) {
                const std::uint64_t id = c.count();
                if (id >= dimensions.size())
                    return corrupt("a variable names a dimension that does not exist");
                if (dimensions[id] == 0 && d == 0) {
                    v.record = true;  // the unlimited dimension, which comes first
                } else {
                    elements *= dimensions[id];
                }
            }
            skipAttributes(c);
            const std::uint64_t type = typeBytes(c.u32());
            c.count();  // vsize: capped for huge variables, so computed from the shape
            v.begin = version == 1 ? c.u32() : c.read(8);
            if (type == 0) return corrupt("a variable has an unknown type");
            v.bytes = elements * type;
            variables.push_back(v);
        }
    }
    if (!c.ok()) return corrupt("it declares more than the file holds (or a wrong attribute tag)");

    std::uint64_t recordBytes = 0;
    std::size_t recordVariables = 0;
    for (const Variable& v : variables) {
        if (!v.record) continue;
        ++recordVariables;
        recordBytes += (v.bytes + 3U) & ~std::uint64_t{3};
    }
    std::uint64_t end = 0;
    for (const Variable& v : variables) {
        if (!v.record) {
            end = std::max(end, v.begin + v.bytes);
        } else if (numrecs > 0 && numrecs != kStreaming) {
            // A lone record variable is not padded (the spec's special case).
            const std::uint64_t stride = recordVariables == 1 ? v.bytes : recordBytes;
            end = std::max(end, v.begin + (numrecs - 1) * stride + v.bytes);
        }
    }
    return std::optional<std::uint64_t>{end};
}

}  // namespace terrain::io::detail
