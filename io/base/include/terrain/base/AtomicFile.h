// AtomicFile: every file the project writes goes to a temporary name in its destination
// folder and is renamed into place only after it was written and closed successfully, so
// no reader ever sees a half-written file and a failed write leaves nothing behind.
#pragma once

#include "terrain/base/Result.h"

#include <filesystem>
#include <functional>
#include <string_view>

namespace terrain {

/// A reserved temporary file next to a destination; move-only. Destroying it before
/// commit() removes the temporary file. Any thread (one owner at a time).
class AtomicFile {
public:
    /// Creates an empty temporary file in path's folder (the same file system, so the
    /// final rename is atomic) whose name keeps path's extension (libraries such as
    /// OpenImageIO pick the format from it): "<folder>/.<stem>.tmp-<pid>-<n><ext>".
    /// Fails, naming `path`, when the folder is missing or not writable.
    static Result<AtomicFile> create(const std::filesystem::path& path);

    AtomicFile(AtomicFile&& other) noexcept;
    AtomicFile& operator=(AtomicFile&& other) noexcept;
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    ~AtomicFile();

    /// The destination.
    const std::filesystem::path& path() const { return m_path; }
    /// Where to write (any writer may truncate and rewrite it).
    const std::filesystem::path& temporaryPath() const { return m_temporaryPath; }

    /// Renames the temporary file onto path(), replacing an existing file. On failure
    /// the temporary file is removed. Call once, after the writer closed the file.
    Status commit();

    /// Removes the temporary file now (as the destructor would).
    void discard();

private:
    AtomicFile(std::filesystem::path path, std::filesystem::path temporaryPath);

    std::filesystem::path m_path;
    std::filesystem::path m_temporaryPath;
    bool m_pending = false;  // a temporary file exists and is ours to remove
};

/// Writes `path` through an AtomicFile: runs write(temporaryPath) and commits if it
/// succeeds; otherwise the temporary file is removed and write's Error returned.
Status writeAtomically(const std::filesystem::path& path,
                       const std::function<Status(const std::filesystem::path&)>& write);

/// Writes `text` to `path`, byte for byte, through writeAtomically: readers see the old file
/// or the whole new one. Errors name `path` (a folder missing or not writable, a failed
/// write, a failed rename); nothing is left behind then. Any thread.
Status writeTextAtomically(const std::filesystem::path& path, std::string_view text);

}  // namespace terrain
