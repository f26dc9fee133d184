// KeyValueSpec: the built-in sources' names, "prefix:key=value,key=value,…"
// ("procedural:size=1025,seed=1", "planet:level=9,west=10"). One parser, so every such name
// refuses a bad item with the same message: the name, what is wrong, the item and the keys.
#pragma once

#include "terrain/base/Result.h"

#include <charconv>
#include <functional>
#include <string_view>

namespace terrain::io {

enum class SpecKey { Taken, BadValue, Unknown };

/// Calls `take(key, value)` for every item after `prefix` (empty items are skipped). Errors:
/// "<spec>: expected key=value, got '<item>' (keys: <keys>)", "… bad value in …", "… unknown
/// key in …".
Status parseKeyValueSpec(
    std::string_view spec, std::string_view prefix, std::string_view keys,
    const std::function<SpecKey(std::string_view key, std::string_view value)>& take);

/// The whole of `text` as a number (std::from_chars).
template <typename T>
bool parseSpecNumber(std::string_view text, T& value) {
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size();
}

}  // namespace terrain::io
