// FakeImagerySource: an ImageryTileSource for tests of imagery streaming (issue 47), with
// deterministic texels per (layer, tile), tiles that are absent and tiles that fail to read,
// chosen by the test; and addImageryLayers(), which gives a test pyramid's manifest imagery
// layers for the I/O thread to open through fakeImageryOpener().
#pragma once

#include "terrain/base/Result.h"
#include "terrain/iothread/IoThread.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/ImageryTileSource.h"
#include "terrain/pyramid/PyramidManifest.h"

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace terrain::test {

/// What the fake layers hold; shared by the sources of every layer (read by the I/O thread:
/// the functions must be pure and set before the thread starts).
struct FakeImageryRules {
    std::function<bool(int layer, const io::PatchId&)> absent;  ///< no tile there
    std::function<bool(int layer, const io::PatchId&)> fails;   ///< reading it fails
    /// Bytes of texels a present tile gets (a broken source when not kImageryTileBytes).
    std::size_t texelBytes = io::kImageryTileBytes;
    /// readTile calls so far, all layers (the test reads it between frames).
    std::shared_ptr<std::atomic<int>> reads = std::make_shared<std::atomic<int>>(0);
    /// A layer at a URL, as far as its counts go: opening it made one request (its index)
    /// and each readTile one more, fetching kFakeImageryFileBytes.
    bool overHttp = false;
};

inline constexpr std::uint64_t kFakeImageryFileBytes = 1000;

/// Texel (x, y) of the fake tile `id` of `layer`: a pattern unique to the tile.
inline std::uint32_t fakeImageryTexel(int layer, const io::PatchId& id, int x, int y) {
    const auto r = static_cast<std::uint32_t>((x + 3 * id.x + 17 * layer) & 255);
    const auto g = static_cast<std::uint32_t>((y + 5 * id.y) & 255);
    const auto b = static_cast<std::uint32_t>((40 * id.level + 7 * layer) & 255);
    return r | (g << 8U) | (b << 16U) | (255U << 24U);
}

inline void fillFakeImagery(int layer, const io::PatchId& id, std::size_t bytes,
                            io::ImageryTile& out) {
    out.id = id;
    out.info = {.present = true, .presentChildren = 0xF, .opaque = true};
    out.rgba.resize(bytes);
    for (std::size_t i = 0; i + 4 <= bytes; i += 4) {
        const int texel = static_cast<int>(i / 4);
        const std::uint32_t c = fakeImageryTexel(layer, id, texel % io::kImageryTileTexels,
                                                 texel / io::kImageryTileTexels);
        for (std::size_t k = 0; k < 4; ++k)
            out.rgba[i + k] = static_cast<std::uint8_t>(c >> (8U * k));
    }
}

class FakeImagerySource final : public io::ImageryTileSource {
public:
    FakeImagerySource(int layer, FakeImageryRules rules)
        : m_layer(layer), m_rules(std::move(rules)) {}

    Status readTile(const io::PatchId& id, io::ImageryTile& out) override {
        ++*m_rules.reads;
        ++m_ownReads;
        if (m_rules.fails && m_rules.fails(m_layer, id))
            return Error{"fake imagery layer " + std::to_string(m_layer) + ": cannot read tile L" +
                         std::to_string(id.level) + " (" + std::to_string(id.x) + ", " +
                         std::to_string(id.y) + ")"};
        if (m_rules.absent && m_rules.absent(m_layer, id)) {
            out.id = id;
            out.info = {};
            out.rgba.clear();
            return {};
        }
        fillFakeImagery(m_layer, id, m_rules.texelBytes, out);
        return {};
    }

    remote::RemoteStats remoteStats() const override {
        if (!m_rules.overHttp) return {};
        remote::RemoteStats stats;
        stats.requests = 1 + m_ownReads;
        stats.fetched = 1 + m_ownReads;
        stats.fetchedBytes = (1 + m_ownReads) * kFakeImageryFileBytes;
        return stats;
    }

private:
    int m_layer;
    FakeImageryRules m_rules;
    std::uint64_t m_ownReads = 0;
};

/// Opens a FakeImagerySource per layer; the layers in `failToOpen` (a bit per layer) fail.
inline io::ImagerySourceOpener fakeImageryOpener(FakeImageryRules rules,
                                                 std::uint32_t failToOpen = 0) {
    return [rules = std::move(rules), failToOpen](
               const io::PyramidManifest& manifest,
               int index) -> Result<std::unique_ptr<io::ImageryTileSource>> {
        if ((failToOpen >> static_cast<unsigned>(index) & 1U) != 0)
            return Error{"fake imagery layer \"" +
                         manifest.imagery[static_cast<std::size_t>(index)].name +
                         "\": cannot be opened"};
        return std::unique_ptr<io::ImageryTileSource>(
            std::make_unique<FakeImagerySource>(index, rules));
    };
}

/// Adds `count` imagery layers ("layer0", …; stored tiles, levels from the root to two below
/// the finest) to the manifest of the pyramid at `dir`.
inline Status addImageryLayers(const std::filesystem::path& dir, int count) {
    auto manifest = io::readManifest(dir);
    if (!manifest) return manifest.error();
    io::PyramidManifest m = std::move(manifest).value();
    for (int k = 0; k < count; ++k) {
        io::ManifestImageryLayer layer;
        layer.name = "layer" + std::to_string(k);
        layer.folder = "imagery/" + layer.name;
        layer.codec = "webp";
        layer.coarsestLevel = m.globe ? io::ManifestGlobe::kLevelOffset : 0;
        layer.finestLevel = m.layout.finestLevel() + 2;
        m.imagery.push_back(layer);
    }
    return io::writeManifest(dir, m);
}

}  // namespace terrain::test
