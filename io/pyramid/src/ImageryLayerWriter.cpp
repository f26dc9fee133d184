// ImageryLayerWriter (ImageryLayerWriter.h). Each tile file is created with a zeroed header
// and table, payloads are appended as tiles arrive (the tables stay in memory: 5 KiB a
// file), and finish() writes every table in place, then layer.json, then renames the folder.
#include "terrain/pyramid/ImageryLayerWriter.h"

#include "ImageryTileFormat.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>

namespace terrain::io {

namespace fs = std::filesystem;

struct ImageryLayerWriter::State {
    fs::path layerDir;
    fs::path temporaryDir;
    fs::path createdParent;  // the parent folder, when create() made it
    imagery::Encoding encoding;
    std::mutex mutex;  // guards everything below
    std::map<imagery::GroupId, imagery::GroupTable> tables;
    std::map<imagery::GroupId, std::uint64_t> fileEnds;
    ImageryLayerIndex index;
    bool finished = false;

    ~State() {
        if (!finished && !temporaryDir.empty()) {
            std::error_code ec;
            fs::remove_all(temporaryDir, ec);
            if (!createdParent.empty()) fs::remove(createdParent, ec);  // only if empty
        }
    }
};

namespace {

Status writeAt(const fs::path& path, std::uint64_t offset, std::span<const std::uint8_t> bytes,
               bool create) {
    std::FILE* file = std::fopen(path.c_str(), create ? "w+b" : "r+b");
    if (!file)
        return Error{
            fmt::format("{}: cannot open for writing: {}", path.string(), std::strerror(errno))};
    bool ok = fseeko(file, static_cast<off_t>(offset), SEEK_SET) == 0 &&
              std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
    const int error = errno;
    ok = (std::fclose(file) == 0) && ok;
    if (!ok) return Error{fmt::format("{}: cannot write: {}", path.string(), std::strerror(error))};
    return {};
}

}  // namespace

ImageryLayerWriter::ImageryLayerWriter(std::unique_ptr<State> state) : m_state(std::move(state)) {}
ImageryLayerWriter::ImageryLayerWriter(ImageryLayerWriter&&) noexcept = default;
ImageryLayerWriter& ImageryLayerWriter::operator=(ImageryLayerWriter&&) noexcept = default;
ImageryLayerWriter::~ImageryLayerWriter() = default;

Result<ImageryLayerWriter> ImageryLayerWriter::create(const fs::path& layerDir,
                                                      const ImageryEncoding& encoding) {
    if (!encoding.lossless && (encoding.quality < 0 || encoding.quality > 100))
        return Error{fmt::format("{}: WebP quality {} is outside 0 … 100", layerDir.string(),
                                 encoding.quality)};
    auto state = std::make_unique<State>();
    state->layerDir = layerDir;
    state->encoding = {encoding.lossless, encoding.quality};
    state->index.lossless = encoding.lossless;
    state->index.quality = encoding.quality;
    const fs::path parent = layerDir.has_parent_path() ? layerDir.parent_path() : fs::path(".");
    const fs::path temporary =
        parent / fmt::format(".{}.tmp-{}", layerDir.filename().string(), ::getpid());
    std::error_code ec;
    if (!fs::exists(parent, ec) && fs::create_directories(parent, ec))
        state->createdParent = parent;
    fs::remove_all(temporary, ec);  // a stale one of this process id: ours by name
    if (!fs::create_directories(temporary, ec) || ec)
        return Error{fmt::format("{}: cannot create {}: {}", layerDir.string(), temporary.string(),
                                 ec ? ec.message() : "exists")};
    state->temporaryDir = temporary;
    return ImageryLayerWriter(std::move(state));
}

const fs::path& ImageryLayerWriter::layerDir() const { return m_state->layerDir; }
const ImageryLayerIndex& ImageryLayerWriter::index() const { return m_state->index; }

Status ImageryLayerWriter::writeTile(const ImageryTile& tile) {
    TERRAIN_ASSERT(!m_state->finished, "writeTile after finish");
    if (!tile.info.present) return {};
    TERRAIN_ASSERT(tile.rgba.size() == kImageryTileBytes, "a present tile's texels");
    std::vector<std::uint8_t> payload;
    if (!imagery::fullyTransparent(tile.rgba)) {
        Result<std::vector<std::uint8_t>> encoded =
            imagery::encodeTexels(tile.rgba, m_state->encoding);
        if (!encoded)
            return Error{fmt::format("{}: tile {} {} {}: {}", m_state->layerDir.string(),
                                     tile.id.level, tile.id.x, tile.id.y, encoded.error().message)};
        payload = std::move(encoded).value();
    }
    const imagery::GroupId group = imagery::groupOf(tile.id);
    const fs::path path = m_state->temporaryDir / imagery::groupPath(group);
    std::lock_guard lock(m_state->mutex);
    const bool created = !m_state->tables.contains(group);
    if (created) {
        std::error_code ec;
        fs::create_directories(path.parent_path(), ec);
        imagery::GroupTable& table = m_state->tables[group];
        table.group = group;
        const std::vector<std::uint8_t> zeros(imagery::kTableEnd, 0);
        if (Status s = writeAt(path, 0, zeros, true); !s) return s;
        m_state->fileEnds[group] = imagery::kTableEnd;
    }
    imagery::TileEntry& entry =
        m_state->tables[group].entries[static_cast<std::size_t>(imagery::indexInGroup(tile.id))];
    TERRAIN_ASSERT(!entry.info.present, "a tile written twice");
    std::uint64_t& end = m_state->fileEnds[group];
    if (!payload.empty()) {
        if (Status s = writeAt(path, end, payload, false); !s) return s;
        entry.offset = end;
        entry.size = static_cast<std::uint32_t>(payload.size());
        entry.crc32 = imagery::crc32Of(payload);
        end += payload.size();
    }
    entry.info = tile.info;
    entry.info.opaque = !payload.empty() && tile.info.opaque;
    return {};
}

Status ImageryLayerWriter::readBack(const PatchId& id, ImageryTile& out) const {
    const State& s = *m_state;
    TERRAIN_ASSERT(!s.finished, "readBack after finish");
    const imagery::GroupId group = imagery::groupOf(id);
    imagery::TileEntry entry;
    {
        std::lock_guard lock(m_state->mutex);
        if (const auto t = s.tables.find(group); t != s.tables.end())
            entry = t->second.entries[static_cast<std::size_t>(imagery::indexInGroup(id))];
    }
    out.id = id;
    out.info = entry.info;
    out.mips.clear();
    if (!entry.info.present) {
        out.rgba.clear();
        return {};
    }
    if (entry.size == 0) {
        out.rgba.assign(kImageryTileBytes, 0);
        return {};
    }
    const fs::path path = s.temporaryDir / imagery::groupPath(group);
    std::vector<std::uint8_t> payload(entry.size);
    std::FILE* file = std::fopen(path.c_str(), "rb");
    bool ok = file && fseeko(file, static_cast<off_t>(entry.offset), SEEK_SET) == 0 &&
              std::fread(payload.data(), 1, payload.size(), file) == payload.size();
    const int error = errno;
    if (file) std::fclose(file);
    if (!ok)
        return Error{fmt::format("{}: tile {} {} {}: cannot read back: {}", path.string(), id.level,
                                 id.x, id.y, std::strerror(error))};
    if (Status d = imagery::decodeTexels(payload, out.rgba); !d)
        return Error{fmt::format("{}: tile {} {} {}: {}", path.string(), id.level, id.x, id.y,
                                 d.error().message)};
    return {};
}

Status ImageryLayerWriter::finish(bool replaceExisting) {
    State& s = *m_state;
    TERRAIN_ASSERT(!s.finished, "finish twice");
    std::lock_guard lock(s.mutex);
    s.index.levels.clear();
    for (const auto& [group, table] : s.tables) {
        const fs::path path = s.temporaryDir / imagery::groupPath(group);
        if (Status w = writeAt(path, 0, imagery::encodeTable(table), false); !w) return w;
        if (s.index.levels.empty() || s.index.levels.back().level != group.level)
            s.index.levels.push_back({group.level, {}});
        std::int64_t present = 0;
        for (const imagery::TileEntry& e : table.entries) present += e.info.present ? 1 : 0;
        s.index.levels.back().files.push_back(
            {group.x, group.y, present, static_cast<std::int64_t>(s.fileEnds[group])});
    }
    // The map orders groups by (level, x, y); the index lists files by (y, x).
    for (ImageryIndexLevel& l : s.index.levels)
        std::sort(l.files.begin(), l.files.end(),
                  [](const auto& a, const auto& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
    if (Status w = writeImageryIndex(s.temporaryDir, s.index); !w) return w;
    std::error_code ec;
    fs::path old;
    if (fs::exists(s.layerDir, ec)) {
        if (!replaceExisting)
            return Error{fmt::format("{}: already exists (replace it to rebuild the layer)",
                                     s.layerDir.string())};
        old = s.layerDir.parent_path() /
              fmt::format(".{}.old-{}", s.layerDir.filename().string(), ::getpid());
        fs::remove_all(old, ec);
        fs::rename(s.layerDir, old, ec);
        if (ec)
            return Error{fmt::format("{}: cannot move the old layer aside: {}", s.layerDir.string(),
                                     ec.message())};
    }
    fs::rename(s.temporaryDir, s.layerDir, ec);
    if (ec) {
        std::error_code back;
        if (!old.empty()) fs::rename(old, s.layerDir, back);
        return Error{fmt::format("{}: cannot rename {} into place: {}", s.layerDir.string(),
                                 s.temporaryDir.string(), ec.message())};
    }
    s.finished = true;
    if (!old.empty()) fs::remove_all(old, ec);
    return {};
}

}  // namespace terrain::io
