// Small helpers for runtime tests: a temporary folder removed after the test, a scoped
// environment variable, and a substring check for error messages.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "TempFolder.h"

#include <unistd.h>

namespace terrain::test {

// A TempFolder that can also write text files into itself.
class TempDirectory : public TempFolder {
public:
    std::filesystem::path write(std::string_view name, std::string_view text) const {
        const std::filesystem::path file = path() / name;
        std::ofstream out(file, std::ios::binary);
        out << text;
        return file;
    }
};

/// Sets an environment variable for one scope, restoring the previous value after.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : m_name(name) {
        if (const char* old = std::getenv(name); old != nullptr) {
            m_old = old;
            m_hadOld = true;
        }
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (m_hadOld) {
            ::setenv(m_name, m_old.c_str(), 1);
        } else {
            ::unsetenv(m_name);
        }
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* m_name;
    std::string m_old;
    bool m_hadOld = false;
};

inline bool contains(std::string_view text, std::string_view part) {
    return text.find(part) != std::string_view::npos;
}

}  // namespace terrain::test
