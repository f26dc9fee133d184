// BuildOutput: how every pyramid build reaches the disk (docs/pyramid-format.md): into
// "<output>.partial-<pid>" (a region build: "<output>.parts"), removed unless the build
// completes, then swapped into place so
// an interrupted or failed build never leaves a valid-looking pyramid or loses the old one.
#pragma once

#include "terrain/base/Result.h"

#include <cstdint>
#include <filesystem>

namespace terrain::io {

/// The partial folder of a build; removes itself unless commit() moved it into place.
class PartialBuildFolder {
public:
    /// Refuses an existing `output` unless `overwrite`; creates "<output>.partial-<pid>".
    static Result<PartialBuildFolder> create(const std::filesystem::path& output, bool overwrite);
    /// A folder another process filled (a region build's staging folder): kept, not removed,
    /// when commit() is never reached, so a failed merge loses no shard. Refuses an existing
    /// `output` unless `overwrite`.
    static Result<PartialBuildFolder> adopt(const std::filesystem::path& output,
                                            const std::filesystem::path& folder, bool overwrite);

    PartialBuildFolder(PartialBuildFolder&& other) noexcept;
    PartialBuildFolder& operator=(PartialBuildFolder&&) = delete;
    PartialBuildFolder(const PartialBuildFolder&) = delete;
    PartialBuildFolder& operator=(const PartialBuildFolder&) = delete;
    ~PartialBuildFolder();

    const std::filesystem::path& path() const { return m_path; }

    /// Moves the finished folder to the output path (the old pyramid, if replacing, is moved
    /// aside first and removed last, or put back if the move fails).
    Status commit();

private:
    PartialBuildFolder(std::filesystem::path output, std::filesystem::path path);
    std::filesystem::path m_output;  // as given, for messages
    std::filesystem::path m_absoluteOutput;
    std::filesystem::path m_path;
    bool m_done = false;
    bool m_keep = false;  // adopted: never removed here
};

/// Refuses a PyramidBuildOptions::maxErrorM that is negative, NaN or infinite, naming
/// `output`; both builders call it before they create anything.
Status checkMaxErrorM(const std::filesystem::path& output, double maxErrorM);

/// Bytes of the regular files under `folder`.
std::uint64_t folderBytes(const std::filesystem::path& folder);

}  // namespace terrain::io
