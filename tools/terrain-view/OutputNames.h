// OutputNames: where the files the viewer writes on a key press go. A command-line flag
// names the first file of its kind (--screenshot is written at exit, --record and
// --telemetry start at launch); files started later with a key get a time-stamped name next
// to it (or in the working folder), never overwriting an earlier one.
#pragma once

#include "terrain/base/Result.h"

#include <filesystem>
#include <string>

namespace terrain::view {

class OutputNames {
public:
    /// `named`: the flag's file, or empty. Key files go to its folder (or the working
    /// folder) as `<prefix>-YYYYMMDD-HHMMSS[-N]<extension>`.
    OutputNames(std::filesystem::path named, std::string prefix, std::string extension);

    /// The flag's file, once (empty if none was given or it was taken already).
    std::filesystem::path takeNamed();
    /// A fresh time-stamped name that does not exist yet.
    std::filesystem::path nextKeyed() const;
    /// takeNamed() if there is one, else nextKeyed().
    std::filesystem::path next();

    const std::filesystem::path& named() const { return m_named; }

private:
    std::filesystem::path m_named;
    std::filesystem::path m_folder;
    std::string m_prefix;
    std::string m_extension;
    bool m_namedTaken = false;
};

/// Checks at start-up that `file` can be created later: its folder exists and is a folder.
/// The error names the file and says what is wrong.
Status checkOutputFolder(const std::filesystem::path& file, const std::string& what);

}  // namespace terrain::view
