// NumberChecks: the command line's checks of a value that must be a positive number, or 0
// or more, with a message a user reads: CLI11's PositiveNumber and NonNegativeNumber printed
// their own range, up to DBL_MAX written out in 309 digits, and let NaN through.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

namespace terrain::tools {

namespace detail {

/// A finite number above 0, or at 0 too where `zeroAllowed`; else the message CLI11 prints
/// after the option's name.
inline std::string checkNumber(const std::string& text, bool zeroAllowed) {
    double value = 0.0;
    if (!CLI::detail::lexical_cast(text, value)) return text + " is not a number";
    if (!std::isfinite(value)) return text + " is not a finite number";
    if (zeroAllowed ? value < 0.0 : value <= 0.0)
        return text + (zeroAllowed ? " is negative: give 0 or more" : " is not a positive number");
    return {};
}

}  // namespace detail

/// --option: "0 is not a positive number".
inline CLI::Validator positiveNumber() {
    return {[](std::string& text) { return detail::checkNumber(text, false); }, "POSITIVE"};
}

/// --option: "-1 is negative: give 0 or more".
inline CLI::Validator nonNegativeNumber() {
    return {[](std::string& text) { return detail::checkNumber(text, true); }, "NONNEGATIVE"};
}

}  // namespace terrain::tools
