// TERRAIN_ASSERT: checks for programmer errors, kept on in release builds.
// Bad data never reaches an assert: it travels as a Result (see Result.h).
#pragma once

#include <cstdio>
#include <cstdlib>

namespace terrain::detail {
[[noreturn]] inline void assertFailed(const char* expression, const char* file, int line,
                                      const char* message) {
    std::fprintf(stderr, "%s:%d: TERRAIN_ASSERT(%s) failed%s%s\n", file, line, expression,
                 message[0] != '\0' ? ": " : "", message);
    std::abort();
}
}  // namespace terrain::detail

#define TERRAIN_ASSERT(expression, ...) \
    ((expression)                       \
         ? static_cast<void>(0)         \
         : ::terrain::detail::assertFailed(#expression, __FILE__, __LINE__, "" __VA_ARGS__))
