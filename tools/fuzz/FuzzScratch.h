// FuzzScratch: what every fuzz target shares. The readers under test take file paths, so
// each input is written to a file in a private scratch folder (in /dev/shm when there is
// one: an input costs no disk I/O), removed when the process exits. When the environment
// variable TERRAIN_FUZZ_SEEDS names a folder, a target's LLVMFuzzerInitialize writes its
// seed inputs there: small valid files made by the project's own writers, which
// scripts/fuzz.sh uses as the starting corpus (nothing is copied from real data).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <system_error>

namespace terrain::fuzz {

namespace fs = std::filesystem;

/// A harness's own mistake (not a finding in the code under test): said, then abort.
[[noreturn]] inline void harnessFailure(const std::string& what) {
    std::fprintf(stderr, "fuzz harness: %s\n", what.c_str());
    std::abort();
}

/// An invariant of the code under test: when it does not hold, that is a finding (abort,
/// which the fuzzer reports as a crash with this input).
inline void require(bool holds, const char* invariant) {
    if (holds) return;
    std::fprintf(stderr, "fuzz finding: %s\n", invariant);
    std::abort();
}

class ScratchFolder {
public:
    ScratchFolder() {
        std::error_code ec;
        const fs::path shm = "/dev/shm";
        const fs::path base = fs::is_directory(shm, ec) ? shm : fs::temp_directory_path();
        m_path = base / ("terrain-fuzz-" + std::to_string(::getpid()));
        fs::remove_all(m_path, ec);
        if (!fs::create_directories(m_path, ec)) harnessFailure("cannot create " + m_path.string());
    }
    ~ScratchFolder() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    const fs::path& path() const { return m_path; }

private:
    fs::path m_path;
};

/// This process's scratch folder.
inline const fs::path& scratch() {
    static const ScratchFolder folder;
    return folder.path();
}

inline void writeFile(const fs::path& path, std::span<const std::uint8_t> bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    if (!out) harnessFailure("cannot write " + path.string());
}

/// The folder named by TERRAIN_FUZZ_SEEDS (created), or nothing when it is not set.
inline std::optional<fs::path> seedFolder() {
    const char* named = std::getenv("TERRAIN_FUZZ_SEEDS");
    if (named == nullptr || *named == '\0') return std::nullopt;
    std::error_code ec;
    fs::create_directories(named, ec);
    if (!fs::is_directory(named)) harnessFailure(std::string("cannot create ") + named);
    return fs::path(named);
}

/// Copies `file` into the seed folder as `name`, when there is a seed folder.
inline void addSeed(const fs::path& file, const std::string& name) {
    if (const auto seeds = seedFolder()) {
        std::error_code ec;
        fs::copy_file(file, *seeds / name, fs::copy_options::overwrite_existing, ec);
        if (ec) harnessFailure("cannot copy the seed " + file.string() + ": " + ec.message());
    }
}

}  // namespace terrain::fuzz
