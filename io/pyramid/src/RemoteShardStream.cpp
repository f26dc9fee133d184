#include "RemoteShardStream.h"

#include <Iex.h>

#include <algorithm>
#include <span>

namespace terrain::io {
namespace {

// What the header walk reads at a time: a few attributes need several reads, a block's worth
// of them one.
constexpr std::uint64_t kBufferBytes = 4096;

}  // namespace

RemoteExrStream::RemoteExrStream(remote::RemoteFile& file)
    : IStream(file.url().c_str()), m_file(file) {}

bool RemoteExrStream::read(char c[], int n) {
    if (n < 0) throw Iex::InputExc("negative read");
    const auto count = static_cast<std::uint64_t>(n);
    if (m_position > m_file.size() || count > m_file.size() - m_position)
        throw Iex::InputExc("unexpected end of file");
    if (Status got = m_file.read(m_position, std::span<char>(c, count)); !got)
        throw Iex::InputExc(got.error().message);
    m_position += count;
    return m_position < m_file.size();
}

RemoteFileBuffer::int_type RemoteFileBuffer::underflow() {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    const std::uint64_t next = m_bufferStart + static_cast<std::uint64_t>(gptr() - eback());
    if (next >= m_file.size()) return traits_type::eof();
    m_buffer.resize(std::min(kBufferBytes, m_file.size() - next));
    if (!m_file.read(next, m_buffer)) return traits_type::eof();  // the walk then fails
    m_bufferStart = next;
    setg(m_buffer.data(), m_buffer.data(), m_buffer.data() + m_buffer.size());
    return traits_type::to_int_type(*gptr());
}

RemoteFileBuffer::pos_type RemoteFileBuffer::seekoff(off_type offset, std::ios_base::seekdir from,
                                                     std::ios_base::openmode which) {
    const auto here = static_cast<off_type>(m_bufferStart) + (gptr() - eback());
    const off_type base = from == std::ios_base::beg   ? 0
                          : from == std::ios_base::cur ? here
                                                       : static_cast<off_type>(m_file.size());
    return seekpos(pos_type(base + offset), which);
}

RemoteFileBuffer::pos_type RemoteFileBuffer::seekpos(pos_type position,
                                                     std::ios_base::openmode /*which*/) {
    const auto at = static_cast<off_type>(position);
    if (at < 0) return pos_type(off_type(-1));
    const auto start = static_cast<off_type>(m_bufferStart);
    if (at >= start && at <= start + static_cast<off_type>(m_buffer.size()) && eback() != nullptr) {
        setg(eback(), eback() + (at - start), egptr());
    } else {  // elsewhere: the next underflow reads there
        m_buffer.clear();
        m_bufferStart = static_cast<std::uint64_t>(at);
        setg(nullptr, nullptr, nullptr);
    }
    return position;
}

}  // namespace terrain::io
