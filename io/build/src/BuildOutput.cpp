#include "BuildOutput.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>

#include <string>
#include <system_error>
#include <utility>

namespace terrain::io {

namespace fs = std::filesystem;

PartialBuildFolder::PartialBuildFolder(fs::path output, fs::path path)
    : m_output(std::move(output)), m_path(std::move(path)) {
    std::error_code ec;
    m_absoluteOutput = fs::absolute(m_output, ec);
}

PartialBuildFolder::PartialBuildFolder(PartialBuildFolder&& other) noexcept
    : m_output(std::move(other.m_output)),
      m_absoluteOutput(std::move(other.m_absoluteOutput)),
      m_path(std::move(other.m_path)),
      m_done(other.m_done),
      m_keep(other.m_keep) {
    other.m_done = true;  // the moved-from folder owns nothing
}

PartialBuildFolder::~PartialBuildFolder() {
    if (!m_done && !m_keep) {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
}

Result<PartialBuildFolder> PartialBuildFolder::create(const fs::path& output, bool overwrite) {
    std::error_code ec;
    if (fs::exists(output, ec) && !overwrite)
        return Error{output.string() + ": already exists (pass --overwrite to replace it)"};
    const fs::path absoluteOutput = fs::absolute(output, ec);
    PartialBuildFolder folder(
        output, absoluteOutput.parent_path() /
                    (absoluteOutput.filename().string() + ".partial-" + std::to_string(getpid())));
    fs::create_directories(folder.path() / "tmp", ec);
    if (ec)
        return Error{folder.path().string() + ": cannot create the output folder: " + ec.message()};
    return folder;
}

Result<PartialBuildFolder> PartialBuildFolder::adopt(const fs::path& output, const fs::path& folder,
                                                     bool overwrite) {
    std::error_code ec;
    if (fs::exists(output, ec) && !overwrite)
        return Error{output.string() + ": already exists (pass --overwrite to replace it)"};
    PartialBuildFolder adopted(output, folder);
    adopted.m_keep = true;
    return adopted;
}

Status PartialBuildFolder::commit() {
    std::error_code ec;
    fs::remove_all(m_path / "tmp", ec);
    const fs::path old = m_absoluteOutput.string() + ".old-" + std::to_string(getpid());
    const bool replacing = fs::exists(m_absoluteOutput, ec);
    if (replacing) {
        fs::rename(m_absoluteOutput, old, ec);
        if (ec)
            return Error{m_output.string() +
                         ": cannot move the existing pyramid aside: " + ec.message()};
    }
    fs::rename(m_path, m_absoluteOutput, ec);
    if (ec) {
        std::error_code ignored;
        if (replacing) fs::rename(old, m_absoluteOutput, ignored);  // put the old one back
        return Error{m_output.string() +
                     ": cannot move the finished pyramid into place: " + ec.message()};
    }
    m_done = true;
    if (replacing) fs::remove_all(old, ec);
    return {};
}

Status checkMaxErrorM(const fs::path& output, double maxErrorM) {
    if (maxErrorM >= 0.0 && std::isfinite(maxErrorM)) return {};
    return Error{
        fmt::format("{}: the maximum storage error must be a finite number of metres "
                    "≥ 0 (0: lossless), not {}",
                    output.string(), maxErrorM)};
}

std::uint64_t folderBytes(const fs::path& folder) {
    std::uint64_t bytes = 0;
    std::error_code ec;
    for (const auto& entry : fs::recursive_directory_iterator(folder, ec))
        if (entry.is_regular_file(ec)) bytes += entry.file_size(ec);
    return bytes;
}

}  // namespace terrain::io
