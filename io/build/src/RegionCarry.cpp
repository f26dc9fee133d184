#include "RegionCarry.h"

#include "CarryArchive.h"
#include "RegionStaging.h"

#include "terrain/base/AtomicFile.h"

#include <fmt/core.h>

#include <cstring>
#include <fstream>
#include <system_error>

namespace terrain::io::detail {
namespace {

namespace fs = std::filesystem;

constexpr char kCarryMagic[8] = {'T', 'R', 'C', 'A', 'R', 'R', 'Y', '2'};

// The summary, which the merge reads alone.
template <typename Archive, typename Carry>
void summaryFields(Archive& a, Carry& c, std::vector<std::int64_t>& builtFrom) {
    a.text(c.fingerprint);
    a.field(c.shard.level);
    a.field(c.shard.x);
    a.field(c.shard.y);
    a.field(c.patches);
    a.field(c.levelMaxError);
    a.field(c.finestLargestQuantErrorM);
    a.field(c.statistics.minHeight);
    a.field(c.statistics.maxHeight);
    a.field(c.statistics.validSamples);
    a.field(c.statistics.noDataSamples);
    a.field(c.phases.readSeconds);
    a.field(c.phases.boundsSeconds);
    a.field(c.phases.writeSeconds);
    a.field(c.seconds);
    a.values(builtFrom);  // x, y pairs
}

// What the parent's task reads.
template <typename Archive, typename Carry>
void parentFields(Archive& a, Carry& c) {
    for (auto* grid : {&c.bounds.approx, &c.bounds.interpolation}) {
        a.field(grid->x0);
        a.field(grid->y0);
        a.field(grid->width);
        a.field(grid->height);
        a.values(grid->values);
    }
    a.field(c.evenX0);
    a.field(c.evenY0);
    a.field(c.evenWidth);
    a.field(c.evenHeight);
    a.values(c.evenHeights);
    a.values(c.evenValid);
    a.values(c.keys);
    a.values(c.errors);
    a.values(c.parentLow);
    a.values(c.parentHigh);
}

bool consistent(const RegionCarry& c) {
    const auto grid = [](const LevelGrid& g) {
        return g.width >= 0 && g.height >= 0 &&
               g.values.size() == static_cast<std::size_t>(g.width * g.height);
    };
    const bool planarEvens =
        c.evenWidth >= 0 && c.evenHeight >= 0 &&
        (c.keys.empty()
             ? c.evenHeights.size() == static_cast<std::size_t>(c.evenWidth * c.evenHeight)
             : c.evenWidth == 0 && c.evenHeight == 0);
    return grid(c.bounds.approx) && grid(c.bounds.interpolation) && planarEvens &&
           c.evenValid.size() == c.evenHeights.size() && c.errors.size() == c.keys.size() &&
           c.parentHigh.size() == c.parentLow.size();
}

}  // namespace

Status writeFileAtomically(const fs::path& path, const std::string& bytes) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    if (ec) return Error{path.parent_path().string() + ": cannot create folder: " + ec.message()};
    return writeAtomically(path, [&](const fs::path& temporary) -> Status {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out)
            return Error{path.string() +
                         ": cannot write: " + std::generic_category().message(errno)};
        return {};
    });
}

fs::path carryPath(const fs::path& staging, const ShardId& s) {
    return staging / "tmp" / "carry" / fmt::format("L{}", s.level) / std::to_string(s.y) /
           (std::to_string(s.x) + ".carry");
}

Status writeCarry(const fs::path& path, const RegionCarry& carry) {
    std::vector<std::int64_t> builtFrom;
    for (const ShardId& s : carry.builtFrom) {
        builtFrom.push_back(s.x);
        builtFrom.push_back(s.y);
    }
    CarryWriter w;
    w.field(kCarryMagic);
    summaryFields(w, carry, builtFrom);
    parentFields(w, carry);
    return writeFileAtomically(path, w.bytes());
}

Result<RegionCarry> readCarry(const fs::path& path, bool whole) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path.string() + ": missing (the shard's task has not finished)"};
    CarryReader r(in);
    char magic[8] = {};
    r.field(magic);
    if (r.failed() || std::memcmp(magic, kCarryMagic, sizeof magic) != 0)
        return Error{path.string() + ": not a shard carry file"};
    RegionCarry c;
    std::vector<std::int64_t> builtFrom;
    summaryFields(r, c, builtFrom);
    if (r.failed() || builtFrom.size() % 2 != 0)
        return Error{path.string() + ": truncated shard carry file"};
    for (std::size_t k = 0; k < builtFrom.size(); k += 2)
        c.builtFrom.push_back({c.shard.level + 1, builtFrom[k], builtFrom[k + 1]});
    if (whole) {
        parentFields(r, c);
        if (r.failed()) return Error{path.string() + ": truncated shard carry file"};
        if (!consistent(c)) return Error{path.string() + ": inconsistent shard carry file"};
    }
    return c;
}

Result<RegionCarry> readShardCarry(const fs::path& staging, const ShardId& shard,
                                   const std::string& fingerprint, bool whole) {
    const fs::path path = carryPath(staging, shard);
    auto carry = readCarry(path, whole);
    if (!carry) return carry.error();
    if (Status origin = checkCarryOrigin(path, fingerprint, carry.value().fingerprint, shard,
                                         carry.value().shard);
        !origin)
        return origin.error();
    return carry;
}

}  // namespace terrain::io::detail
