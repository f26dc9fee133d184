// ExrFileStream: an OpenEXR output stream over a POSIX file that remembers the first write
// error. OpenEXR writes its offset tables in destructors, which swallow exceptions, so a
// full disk at that point would otherwise go unnoticed; close() reports it.
#pragma once

#include "terrain/base/Result.h"

#include <ImfIO.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace terrain::io {

class ExrFileStream final : public Imf::OStream {
public:
    /// Opens (creates, truncates) `path` for writing. Messages name `displayName` (the
    /// file the user knows, e.g. the final name of a temporary file).
    static Result<std::unique_ptr<ExrFileStream>> open(const std::filesystem::path& path,
                                                       const std::string& displayName);

    ~ExrFileStream() override;
    ExrFileStream(const ExrFileStream&) = delete;
    ExrFileStream& operator=(const ExrFileStream&) = delete;

    /// Buffered; throws Iex::ErrnoExc on an I/O error (as OpenEXR expects) after
    /// recording it.
    void write(const char c[], int n) override;
    std::uint64_t tellp() override;
    void seekp(std::uint64_t pos) override;

    /// Flushes and closes the file. Returns the first error of any write, seek, flush or
    /// close ("<displayName>: cannot write: No space left on device").
    Status close();

    /// The first I/O error ("<displayName>: cannot write: …"), or empty.
    const std::string& firstError() const { return m_firstError; }

private:
    ExrFileStream(const std::filesystem::path& path, std::string displayName, int fd);
    void flushBuffer();  // throws Iex::ErrnoExc after recording the error
    [[noreturn]] void fail(const char* operation, int error);

    std::string m_name;  // for messages
    int m_fd = -1;
    std::vector<char> m_buffer;
    std::size_t m_used = 0;        // bytes of m_buffer not yet written
    std::uint64_t m_position = 0;  // file offset of m_buffer[0]
    std::string m_firstError;      // empty while all went well
};

}  // namespace terrain::io
