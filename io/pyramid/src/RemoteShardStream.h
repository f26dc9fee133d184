// RemoteShardStream: a shard file at a URL read by ranges (remote::RemoteFile) as OpenEXR and
// the header check read a file, so that opening a shard fetches its headers, offset tables and
// patchInfo tile, and reading a patch fetches that patch's bytes, not the whole shard
// (issue 49: a 9 MB globe shard's first patch cost 9 MB; under packet loss it waited for every
// loss in them).
#pragma once

#include "terrain/remote/RemoteFiles.h"

#include <ImfIO.h>

#include <cstdint>
#include <streambuf>
#include <vector>

namespace terrain::io {

/// OpenEXR's input stream over a RemoteFile. A failed read throws Iex::InputExc with the
/// RemoteFile's message (the URL and what went wrong), which the reader reports as a damaged
/// shard: the patch drawn from its ancestors, as for a local read error.
class RemoteExrStream final : public Imf::IStream {
public:
    explicit RemoteExrStream(remote::RemoteFile& file);

    bool read(char c[], int n) override;
    std::uint64_t tellg() override { return m_position; }
    void seekg(std::uint64_t position) override { m_position = position; }

private:
    remote::RemoteFile& m_file;
    std::uint64_t m_position = 0;
};

/// A std::streambuf over a RemoteFile, for ExrHeaderCheck's walk over the headers (an
/// std::istream): reads a block at a time, seeks anywhere.
class RemoteFileBuffer final : public std::streambuf {
public:
    explicit RemoteFileBuffer(remote::RemoteFile& file) : m_file(file) {}

protected:
    int_type underflow() override;
    pos_type seekoff(off_type offset, std::ios_base::seekdir from,
                     std::ios_base::openmode which) override;
    pos_type seekpos(pos_type position, std::ios_base::openmode which) override;

private:
    remote::RemoteFile& m_file;
    std::vector<char> m_buffer;
    std::uint64_t m_bufferStart = 0;  // file offset of m_buffer[0]
};

}  // namespace terrain::io
