// Result<T>: a value or an Error whose message names the file and what is wrong.
// Used wherever bad data (a broken DEM, a corrupt tile) can arrive; never throws.
#pragma once

#include "terrain/base/Assert.h"

#include <string>
#include <utility>
#include <variant>

namespace terrain {

struct Error {
    std::string message;  ///< "<file>: <what is wrong>", ready to show to a user.
};

template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : m_state(std::move(value)) {}      // NOLINT: implicit by design
    Result(Error error) : m_state(std::move(error)) {}  // NOLINT: implicit by design

    bool ok() const { return std::holds_alternative<T>(m_state); }
    explicit operator bool() const { return ok(); }

    T& value() & {
        TERRAIN_ASSERT(ok(), "Result::value() on an error");
        return std::get<T>(m_state);
    }
    const T& value() const& {
        TERRAIN_ASSERT(ok(), "Result::value() on an error");
        return std::get<T>(m_state);
    }
    T&& value() && {
        TERRAIN_ASSERT(ok(), "Result::value() on an error");
        return std::get<T>(std::move(m_state));
    }
    const Error& error() const {
        TERRAIN_ASSERT(!ok(), "Result::error() on a value");
        return std::get<Error>(m_state);
    }

private:
    std::variant<T, Error> m_state;
};

/// Result of an operation with no value: success or an Error.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : m_error(std::move(error)), m_failed(true) {}  // NOLINT: implicit

    bool ok() const { return !m_failed; }
    explicit operator bool() const { return ok(); }
    const Error& error() const {
        TERRAIN_ASSERT(m_failed, "Status::error() on success");
        return m_error;
    }

private:
    Error m_error;
    bool m_failed = false;
};

}  // namespace terrain
