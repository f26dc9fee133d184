#include "ShardCarry.h"

#include "CarryArchive.h"

#include "terrain/base/AtomicFile.h"

#include <fmt/core.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

namespace terrain::io::detail {
namespace {

namespace fs = std::filesystem;

constexpr char kCarryMagic[8] = {'T', 'R', 'C', 'A', 'R', 'R', 'Y', '1'};
constexpr char kEdgeMagic[8] = {'T', 'R', 'E', 'D', 'G', 'E', '0', '1'};

// The summary, which the merge reads alone.
template <typename Archive, typename Carry>
void summaryFields(Archive& a, Carry& c) {
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
}

// What the coarser level's task reads.
template <typename Archive, typename Carry>
void boundsAndSampleFields(Archive& a, Carry& c) {
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

Status writeCarry(const fs::path& path, const ShardCarry& carry) {
    CarryWriter w;
    w.field(kCarryMagic);
    summaryFields(w, carry);
    boundsAndSampleFields(w, carry);
    return writeFileAtomically(path, w.bytes());
}

Result<ShardCarry> readCarry(const fs::path& path, bool whole) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path.string() + ": missing (the shard's task has not finished)"};
    CarryReader r(in);
    char magic[8] = {};
    r.field(magic);
    if (r.failed() || std::memcmp(magic, kCarryMagic, sizeof magic) != 0)
        return Error{path.string() + ": not a shard carry file"};
    ShardCarry c;
    summaryFields(r, c);
    if (whole) {
        boundsAndSampleFields(r, c);
        const auto grid = [](const LevelGrid& g) {
            return g.width >= 0 && g.height >= 0 &&
                   g.values.size() == static_cast<std::size_t>(g.width * g.height);
        };
        const auto samples = static_cast<std::size_t>(std::max<std::int64_t>(0, c.evenWidth) *
                                                      std::max<std::int64_t>(0, c.evenHeight));
        if (!r.failed() && (!grid(c.bounds.approx) || !grid(c.bounds.interpolation) ||
                            c.evenHeights.size() != samples || c.evenValid.size() != samples))
            return Error{path.string() + ": inconsistent shard carry file"};
    }
    if (r.failed()) return Error{path.string() + ": truncated shard carry file"};
    return c;
}

fs::path edgePath(const fs::path& staging, bool east, std::int64_t index) {
    return staging / "tmp" / "edges" / fmt::format("{}-{}.f32", east ? "east" : "south", index);
}

Status writeEdge(const fs::path& path, const EdgeRun& run) {
    CarryWriter w;
    w.field(kEdgeMagic);
    w.field(run.first);
    w.values(run.values);
    return writeFileAtomically(path, w.bytes());
}

Result<EdgeRun> readEdge(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path.string() + ": missing (the edge shard's task has not finished)"};
    CarryReader r(in);
    char magic[8] = {};
    r.field(magic);
    EdgeRun run;
    r.field(run.first);
    r.values(run.values);
    if (r.failed() || std::memcmp(magic, kEdgeMagic, sizeof magic) != 0)
        return Error{path.string() + ": not a DEM edge file, or truncated"};
    return run;
}

}  // namespace terrain::io::detail
