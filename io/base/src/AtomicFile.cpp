// Temporary-then-rename file writing (see AtomicFile.h). POSIX: rename(2) within one file
// system replaces the destination atomically.
#include "terrain/base/AtomicFile.h"

#include <fmt/format.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

namespace terrain {

namespace {

std::atomic<unsigned> g_temporaryCounter{0};

std::string folderOf(const std::filesystem::path& path) {
    const std::filesystem::path parent = path.parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path, std::filesystem::path temporaryPath)
    : m_path(std::move(path)), m_temporaryPath(std::move(temporaryPath)), m_pending(true) {}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : m_path(std::move(other.m_path)),
      m_temporaryPath(std::move(other.m_temporaryPath)),
      m_pending(std::exchange(other.m_pending, false)) {}

AtomicFile& AtomicFile::operator=(AtomicFile&& other) noexcept {
    if (this != &other) {
        discard();
        m_path = std::move(other.m_path);
        m_temporaryPath = std::move(other.m_temporaryPath);
        m_pending = std::exchange(other.m_pending, false);
    }
    return *this;
}

AtomicFile::~AtomicFile() { discard(); }

Result<AtomicFile> AtomicFile::create(const std::filesystem::path& path) {
    if (path.empty()) return Error{"(empty path): no output file name given"};
    if (!path.has_filename())
        return Error{fmt::format("{}: the path names a folder, not a file", path.string())};
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        return Error{fmt::format("{}: is a folder, not a file", path.string())};
    const std::filesystem::path folder = path.parent_path();
    const std::string stem = path.stem().string();
    const std::string extension = path.extension().string();
    // O_EXCL: never reuse a name another writer holds; retry on the (unlikely) clash.
    for (int attempt = 0; attempt < 100; ++attempt) {
        const std::string name = fmt::format(".{}.tmp-{}-{}{}", stem, ::getpid(),
                                             g_temporaryCounter.fetch_add(1), extension);
        std::filesystem::path temporary =
            folder.empty() ? std::filesystem::path(name) : folder / name;
        const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return AtomicFile(path, std::move(temporary));
        }
        if (errno != EEXIST) {
            return Error{fmt::format("{}: cannot create a file in folder '{}': {}", path.string(),
                                     folderOf(path), std::strerror(errno))};
        }
    }
    return Error{fmt::format("{}: cannot find a free temporary name in folder '{}'", path.string(),
                             folderOf(path))};
}

Status AtomicFile::commit() {
    TERRAIN_ASSERT(m_pending, "AtomicFile::commit() without a pending temporary file");
    std::error_code ec;
    std::filesystem::rename(m_temporaryPath, m_path, ec);
    if (ec) {
        discard();
        return Error{fmt::format("{}: cannot move the finished file into place: {}",
                                 m_path.string(), ec.message())};
    }
    m_pending = false;
    return {};
}

void AtomicFile::discard() {
    if (!m_pending) return;
    std::error_code ec;
    std::filesystem::remove(m_temporaryPath, ec);  // nothing more to do if this fails
    m_pending = false;
}

Status writeAtomically(const std::filesystem::path& path,
                       const std::function<Status(const std::filesystem::path&)>& write) {
    Result<AtomicFile> file = AtomicFile::create(path);
    if (!file) return file.error();
    if (Status written = write(file.value().temporaryPath()); !written) return written;
    return file.value().commit();
}

Status writeTextAtomically(const std::filesystem::path& path, std::string_view text) {
    return writeAtomically(path, [&](const std::filesystem::path& temporary) -> Status {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
        out.close();
        if (!out)
            return Error{fmt::format("{}: cannot write: {}", path.string(), std::strerror(errno))};
        return {};
    });
}

}  // namespace terrain
