// Output file names: the flag's, then time-stamped ones.
#include "OutputNames.h"

#include <unistd.h>

#include <ctime>
#include <system_error>
#include <utility>

namespace terrain::view {

OutputNames::OutputNames(std::filesystem::path named, std::string prefix, std::string extension)
    : m_named(std::move(named)),
      m_folder(m_named.empty() ? std::filesystem::path() : m_named.parent_path()),
      m_prefix(std::move(prefix)),
      m_extension(std::move(extension)) {}

std::filesystem::path OutputNames::takeNamed() {
    if (m_named.empty() || m_namedTaken) return {};
    m_namedTaken = true;
    return m_named;
}

std::filesystem::path OutputNames::nextKeyed() const {
    const std::time_t now = std::time(nullptr);
    std::tm local{};
    localtime_r(&now, &local);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
    const std::string base = m_prefix + "-" + stamp;
    std::error_code ec;
    for (int n = 1;; ++n) {
        const std::string name = n == 1 ? base : base + "-" + std::to_string(n);
        const std::filesystem::path candidate = m_folder / (name + m_extension);
        if (!std::filesystem::exists(candidate, ec)) return candidate;
    }
}

std::filesystem::path OutputNames::next() {
    std::filesystem::path named = takeNamed();
    return named.empty() ? nextKeyed() : named;
}

Status checkOutputFolder(const std::filesystem::path& file, const std::string& what) {
    const std::filesystem::path folder =
        file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec)) {
        return Error{file.string() + ": cannot write the " + what + ": the folder " +
                     folder.string() + " does not exist"};
    }
    if (::access(folder.c_str(), W_OK) != 0) {
        return Error{file.string() + ": cannot write the " + what + ": the folder " +
                     folder.string() + " is not writable"};
    }
    if (std::filesystem::is_directory(file, ec)) {
        return Error{file.string() + ": cannot write the " + what + ": it is a folder"};
    }
    return {};
}

}  // namespace terrain::view
