// ImageryTileReader (ImageryTileReader.h): the index says which files exist; a few files stay
// open with their parsed tables (least recently used closed first).
#include "terrain/pyramid/ImageryTileReader.h"
#include "terrain/remote/RemoteFiles.h"

#include "ImageryTileFormat.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <list>
#include <set>

namespace terrain::io {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kOpenFiles = 4;

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

struct OpenGroup {
    imagery::GroupId group;
    fs::path path;
    std::unique_ptr<std::FILE, FileCloser> file;
    imagery::GroupTable table;
};

Status readAt(std::FILE* file, std::uint64_t offset, std::span<std::uint8_t> bytes) {
    if (fseeko(file, static_cast<off_t>(offset), SEEK_SET) != 0 ||
        std::fread(bytes.data(), 1, bytes.size(), file) != bytes.size())
        return Error{std::ferror(file) ? std::strerror(errno) : "truncated"};
    return {};
}

}  // namespace

struct ImageryTileReader::State {
    fs::path layerDir;
    int coarsestLevel = 0;
    int finestLevel = 0;
    ImageryLayerIndex index;
    std::set<imagery::GroupId> listed;
    std::list<OpenGroup> open;  // most recently used first
    std::vector<std::uint8_t> payload;
    // A pyramid at a URL: its tile files' local copies (issue 49); null for a folder.
    std::unique_ptr<remote::RemoteFiles> remote;
    std::uint64_t storedBytesRead = 0;  // the tile payloads read

    // Where to open `path` from: itself, or its local copy when it is a URL.
    Result<fs::path> localFileOf(const fs::path& path) {
        if (!remote) return path;
        return remote->localCopy(path.string());
    }

    std::string tileText(const PatchId& id) const {
        return fmt::format("tile (level {}, x {}, y {})", id.level, id.x, id.y);
    }

    Result<OpenGroup*> openGroup(const imagery::GroupId& group) {
        for (auto it = open.begin(); it != open.end(); ++it)
            if (it->group == group) {
                open.splice(open.begin(), open, it);
                return &open.front();
            }
        OpenGroup g;
        g.group = group;
        g.path = layerDir / imagery::groupPath(group);
        Result<fs::path> local = localFileOf(g.path);
        if (!local) return local.error();
        g.file.reset(std::fopen(local.value().c_str(), "rb"));
        if (!g.file)
            return Error{
                fmt::format("{}: missing tile file: {}", g.path.string(), std::strerror(errno))};
        std::FILE* f = g.file.get();
        if (fseeko(f, 0, SEEK_END) != 0)
            return Error{fmt::format("{}: cannot seek: {}", g.path.string(), std::strerror(errno))};
        const auto size = static_cast<std::uint64_t>(ftello(f));
        std::vector<std::uint8_t> head(std::min<std::uint64_t>(size, imagery::kTableEnd));
        if (Status s = readAt(f, 0, head); !s)
            return Error{fmt::format("{}: {}", g.path.string(), s.error().message)};
        Result<imagery::GroupTable> table = imagery::decodeTable(head, size);
        if (!table) return Error{fmt::format("{}: {}", g.path.string(), table.error().message)};
        if (!(table.value().group == group))
            return Error{fmt::format("{}: holds the tiles of level {} group ({}, {}), not its own",
                                     g.path.string(), table.value().group.level,
                                     table.value().group.x, table.value().group.y)};
        g.table = std::move(table).value();
        if (open.size() >= kOpenFiles) open.pop_back();
        open.push_front(std::move(g));
        return &open.front();
    }
};

ImageryTileReader::ImageryTileReader(std::unique_ptr<State> state) : m_state(std::move(state)) {}
ImageryTileReader::~ImageryTileReader() = default;

Result<std::unique_ptr<ImageryTileReader>> ImageryTileReader::open(const fs::path& layerDir,
                                                                   int coarsestLevel,
                                                                   int finestLevel) {
    Result<std::unique_ptr<remote::RemoteFiles>> files = remote::filesFor(layerDir.string());
    if (!files) return files.error();
    auto state = std::make_unique<State>();
    state->remote = std::move(files).value();
    // Through the reader's own RemoteFiles, so its counts include the index.
    Result<ImageryLayerIndex> index = readImageryIndex(layerDir, state->remote.get());
    if (!index) return index.error();
    state->layerDir = layerDir;
    state->coarsestLevel = coarsestLevel;
    state->finestLevel = finestLevel;
    state->index = std::move(index).value();
    for (const ImageryIndexLevel& l : state->index.levels) {
        if (l.level < coarsestLevel || l.level > finestLevel)
            return Error{
                fmt::format("{}: layer.json lists level {}, outside the layer's levels "
                            "{} … {}",
                            layerDir.string(), l.level, coarsestLevel, finestLevel)};
        for (const ImageryIndexFile& f : l.files) state->listed.insert({l.level, f.x, f.y});
    }
    return std::unique_ptr<ImageryTileReader>(new ImageryTileReader(std::move(state)));
}

const ImageryLayerIndex& ImageryTileReader::index() const { return m_state->index; }

remote::RemoteStats ImageryTileReader::remoteStats() const {
    return m_state->remote ? m_state->remote->stats() : remote::RemoteStats{};
}

std::uint64_t ImageryTileReader::storedBytesRead() const { return m_state->storedBytesRead; }

Status ImageryTileReader::readTile(const PatchId& id, ImageryTile& out) {
    State& s = *m_state;
    out.id = id;
    out.info = {};
    out.rgba.clear();
    if (id.level < s.coarsestLevel || id.level > s.finestLevel || id.x < 0 || id.y < 0)
        return Error{fmt::format("{}: {} is outside the layer's levels {} … {}",
                                 s.layerDir.string(), s.tileText(id), s.coarsestLevel,
                                 s.finestLevel)};
    const imagery::GroupId group = imagery::groupOf(id);
    if (!s.listed.contains(group)) return {};  // no file: no tile there
    Result<OpenGroup*> opened = s.openGroup(group);
    if (!opened)
        return Error{fmt::format("{} ({}): {}", s.layerDir.string(), s.tileText(id),
                                 opened.error().message)};
    OpenGroup& g = *opened.value();
    const imagery::TileEntry& e =
        g.table.entries[static_cast<std::size_t>(imagery::indexInGroup(id))];
    if (!e.info.present) return {};
    out.info = e.info;
    if (e.size == 0) {  // present, fully transparent
        out.rgba.assign(kImageryTileBytes, 0);
        return {};
    }
    s.payload.resize(e.size);
    if (Status r = readAt(g.file.get(), e.offset, s.payload); !r)
        return Error{fmt::format("{}: {}: {}", g.path.string(), s.tileText(id), r.error().message)};
    s.storedBytesRead += e.size;
    if (imagery::crc32Of(s.payload) != e.crc32)
        return Error{fmt::format("{}: {}: CRC-32 mismatch (corrupt payload)", g.path.string(),
                                 s.tileText(id))};
    if (Status d = imagery::decodeTexels(s.payload, out.rgba); !d) {
        out.info = {};
        out.rgba.clear();
        return Error{fmt::format("{}: {}: {}", g.path.string(), s.tileText(id), d.error().message)};
    }
    return {};
}

Status ImageryTileReader::verifyAll(std::int64_t& tilesChecked) {
    State& s = *m_state;
    tilesChecked = 0;
    for (const ImageryIndexLevel& l : s.index.levels)
        for (const ImageryIndexFile& f : l.files) {
            const fs::path url = s.layerDir / imagery::groupPath({l.level, f.x, f.y});
            Result<fs::path> local = s.localFileOf(url);
            if (!local) return local.error();
            const fs::path& path = local.value();
            std::error_code ec;
            const auto size = fs::file_size(path, ec);
            if (ec)
                return Error{fmt::format("{}: missing tile file: {}", path.string(), ec.message())};
            if (static_cast<std::int64_t>(size) != f.bytes)
                return Error{
                    fmt::format("{}: {} bytes, layer.json says {} (truncated or "
                                "replaced)",
                                path.string(), size, f.bytes)};
            std::vector<std::uint8_t> bytes(size);
            std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
            if (!file)
                return Error{
                    fmt::format("{}: cannot open: {}", path.string(), std::strerror(errno))};
            if (Status r = readAt(file.get(), 0, bytes); !r)
                return Error{fmt::format("{}: {}", path.string(), r.error().message)};
            if (Status c = imagery::checkFile(bytes); !c)
                return Error{fmt::format("{}: {}", path.string(), c.error().message)};
            const Result<imagery::GroupTable> table = imagery::decodeTable(bytes, bytes.size());
            std::int64_t present = 0;
            for (const imagery::TileEntry& e : table.value().entries) present += e.info.present;
            if (!(table.value().group == imagery::GroupId{l.level, f.x, f.y}) ||
                present != f.presentTiles)
                return Error{
                    fmt::format("{}: holds {} tiles of level {} group ({}, {}); "
                                "layer.json says {} of its own",
                                path.string(), present, table.value().group.level,
                                table.value().group.x, table.value().group.y, f.presentTiles)};
            tilesChecked += present;
        }
    return {};
}

Status checkImageryTileFile(std::span<const std::uint8_t> bytes) {
    return imagery::checkFile(bytes);
}

}  // namespace terrain::io
