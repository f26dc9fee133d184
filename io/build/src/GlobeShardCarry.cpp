#include "GlobeShardCarry.h"

#include "CarryArchive.h"
#include "ShardCarry.h"

#include <fmt/core.h>

#include <cstring>
#include <fstream>

namespace terrain::io::detail {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'T', 'R', 'G', 'C', 'A', 'R', 'R', '1'};

template <typename Archive, typename Carry>
void summaryFields(Archive& a, Carry& c) {
    a.text(c.fingerprint);
    a.field(c.shard.level);
    a.field(c.shard.x);
    a.field(c.shard.y);
    a.field(c.patches);
    a.field(c.levelMaxError);
    a.field(c.finestLargestQuantErrorM);
    a.field(c.validSamples);
    a.field(c.noDataSamples);
    a.field(c.minHeight);
    a.field(c.maxHeight);
    a.field(c.phases.readSeconds);
    a.field(c.phases.boundsSeconds);
    a.field(c.phases.writeSeconds);
    a.field(c.seconds);
    a.values(c.childShards);
}

template <typename Archive, typename Carry>
void patchFields(Archive& a, Carry& c) {
    a.values(c.keys);
    a.values(c.errors);
    a.values(c.evenHeights);
    a.values(c.evenValid);
    a.values(c.parentLow);
    a.values(c.parentHigh);
}

}  // namespace

Status writeGlobeCarry(const fs::path& path, const GlobeShardCarry& carry) {
    CarryWriter w;
    w.field(kMagic);
    summaryFields(w, carry);
    patchFields(w, carry);
    return writeFileAtomically(path, w.bytes());
}

Result<GlobeShardCarry> readGlobeCarry(const fs::path& path, bool whole, int quads) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path.string() + ": missing (the shard's task has not finished)"};
    CarryReader r(in);
    char magic[8] = {};
    r.field(magic);
    if (r.failed() || std::memcmp(magic, kMagic, sizeof magic) != 0)
        return Error{path.string() + ": not a globe shard carry file"};
    GlobeShardCarry c;
    summaryFields(r, c);
    if (whole) {
        patchFields(r, c);
        const std::size_t patches = c.keys.size();
        const auto half = static_cast<std::size_t>(quads / 2);
        const std::size_t samples = patches * (half + 1) * (half + 1);
        if (!r.failed() && (c.errors.size() != patches || c.evenHeights.size() != samples ||
                            c.evenValid.size() != samples ||
                            (!c.parentLow.empty() && c.parentLow.size() != patches * half * half) ||
                            c.parentHigh.size() != c.parentLow.size()))
            return Error{path.string() + ": inconsistent globe shard carry file"};
    }
    if (r.failed() || c.childShards.size() % 2 != 0)
        return Error{path.string() + ": truncated globe shard carry file"};
    return c;
}

}  // namespace terrain::io::detail
