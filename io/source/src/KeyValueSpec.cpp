#include "terrain/source/KeyValueSpec.h"

#include <fmt/format.h>

namespace terrain::io {

Status parseKeyValueSpec(std::string_view spec, std::string_view prefix, std::string_view keys,
                         const std::function<SpecKey(std::string_view, std::string_view)>& take) {
    std::string_view rest = spec.substr(std::min(prefix.size(), spec.size()));
    while (!rest.empty()) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
        if (item.empty()) continue;
        const auto bad = [&](std::string_view what) {
            return Error{fmt::format("{}: {} '{}' (keys: {})", spec, what, item, keys)};
        };
        const std::size_t equals = item.find('=');
        if (equals == std::string_view::npos) return bad("expected key=value, got");
        switch (take(item.substr(0, equals), item.substr(equals + 1))) {
            case SpecKey::Taken:
                break;
            case SpecKey::BadValue:
                return bad("bad value in");
            case SpecKey::Unknown:
                return bad("unknown key in");
        }
    }
    return {};
}

}  // namespace terrain::io
