// A buffered POSIX output stream for OpenEXR that keeps the first I/O error (see
// ExrFileStream.h).
#include "ExrFileStream.h"

#include <Iex.h>
#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

namespace terrain::io {
namespace {

// Large enough that a 131² float tile is one or two write(2) calls.
constexpr std::size_t kBufferBytes = std::size_t{1} << 20U;

}  // namespace

Result<std::unique_ptr<ExrFileStream>> ExrFileStream::open(const std::filesystem::path& path,
                                                           const std::string& displayName) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0)
        return Error{
            fmt::format("{}: cannot open for writing: {}", displayName, std::strerror(errno))};
    return std::unique_ptr<ExrFileStream>(new ExrFileStream(path, displayName, fd));
}

ExrFileStream::ExrFileStream(const std::filesystem::path& path, std::string displayName, int fd)
    : Imf::OStream(path.c_str()),
      m_name(std::move(displayName)),
      m_fd(fd),
      m_buffer(kBufferBytes) {}

ExrFileStream::~ExrFileStream() {
    if (m_fd >= 0) ::close(m_fd);  // an unfinished file: its owner removes it
}

void ExrFileStream::fail(const char* operation, int error) {
    if (m_firstError.empty())
        m_firstError = fmt::format("{}: cannot {}: {}", m_name, operation, std::strerror(error));
    Iex::throwErrnoExc(std::string("Cannot ") + operation + " file " + m_name + " (%T).", error);
    std::abort();  // not reached: throwErrnoExc always throws
}

void ExrFileStream::flushBuffer() {
    std::size_t done = 0;
    while (done < m_used) {
        const ssize_t n = ::pwrite(m_fd, m_buffer.data() + done, m_used - done,
                                   static_cast<off_t>(m_position + done));
        if (n < 0) {
            if (errno == EINTR) continue;
            const int error = errno;
            m_used = 0;
            fail("write", error);
        }
        if (n == 0) {
            m_used = 0;
            fail("write", ENOSPC);
        }
        done += static_cast<std::size_t>(n);
    }
    m_position += m_used;
    m_used = 0;
}

void ExrFileStream::write(const char c[], int n) {
    if (!m_firstError.empty()) {
        // Once a write failed the file is broken; say so again rather than go on.
        throw Iex::IoExc(m_firstError);
    }
    auto size = static_cast<std::size_t>(n);
    if (m_used + size > m_buffer.size()) {
        flushBuffer();
        if (size >= m_buffer.size()) {
            // Large chunk: write through without copying.
            std::size_t done = 0;
            while (done < size) {
                const ssize_t w =
                    ::pwrite(m_fd, c + done, size - done, static_cast<off_t>(m_position + done));
                if (w < 0 && errno == EINTR) continue;
                if (w <= 0) fail("write", w < 0 ? errno : ENOSPC);
                done += static_cast<std::size_t>(w);
            }
            m_position += size;
            return;
        }
    }
    std::memcpy(m_buffer.data() + m_used, c, size);
    m_used += size;
}

std::uint64_t ExrFileStream::tellp() { return m_position + m_used; }

void ExrFileStream::seekp(std::uint64_t pos) {
    if (pos == tellp()) return;
    if (!m_firstError.empty()) throw Iex::IoExc(m_firstError);
    flushBuffer();
    m_position = pos;
}

Status ExrFileStream::close() {
    if (m_fd < 0) return Error{fmt::format("{}: closed twice", m_name)};
    if (m_firstError.empty()) {
        try {
            flushBuffer();
        } catch (const std::exception&) {
            // recorded in m_firstError
        }
    }
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0 && m_firstError.empty())
        m_firstError = fmt::format("{}: cannot close: {}", m_name, std::strerror(errno));
    if (!m_firstError.empty()) return Error{m_firstError};
    return {};
}

}  // namespace terrain::io
