// CarryArchive: the binary writer and reader of a region build's temporary files (RegionCarry.h,
// the planar edge files): each file lists its fields once, in a template both visit, so what is
// written and what is read cannot drift apart. Machine byte order (a build's tasks run on one
// kind of machine).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace terrain::io::detail {

class CarryWriter {
public:
    template <typename T>
    void field(const T& value) {
        m_bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));
    }
    template <typename T>
    void values(const std::vector<T>& values) {
        field(static_cast<std::uint64_t>(values.size()));
        m_bytes.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    }
    void text(const std::string& s) {
        field(static_cast<std::uint64_t>(s.size()));
        m_bytes.append(s);
    }
    const std::string& bytes() const { return m_bytes; }

private:
    std::string m_bytes;
};

class CarryReader {
public:
    explicit CarryReader(std::ifstream& in) : m_in(in) {}
    template <typename T>
    void field(T& value) {
        if (!m_failed && !m_in.read(reinterpret_cast<char*>(&value), sizeof(T))) m_failed = true;
    }
    template <typename T>
    void values(std::vector<T>& values) {
        std::uint64_t count = 0;
        field(count);
        if (m_failed || count > kMaxValues) {
            m_failed = true;
            return;
        }
        values.resize(static_cast<std::size_t>(count));
        if (!m_in.read(reinterpret_cast<char*>(values.data()),
                       static_cast<std::streamsize>(count * sizeof(T))))
            m_failed = true;
    }
    void text(std::string& s) {
        std::uint64_t count = 0;
        field(count);
        if (m_failed || count > (1u << 20)) {
            m_failed = true;
            return;
        }
        s.resize(static_cast<std::size_t>(count));
        if (!m_in.read(s.data(), static_cast<std::streamsize>(count))) m_failed = true;
    }
    bool failed() const { return m_failed; }

private:
    static constexpr std::uint64_t kMaxValues = std::uint64_t{1} << 32;
    std::ifstream& m_in;
    bool m_failed = false;
};

}  // namespace terrain::io::detail
