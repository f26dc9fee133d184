// FakeTileResidency: the LOD's TileResidency for tests, deterministic and on one thread
// without GL (cesium-native's SimpleAssetAccessor in spirit): a patch asked for becomes
// resident a chosen number of frames later, at most so many arrive per frame, chosen ids
// fail instead, and a fixed number of layers is handed out with the GPU pool's eviction
// rule (the least recently used layer that is neither pinned nor used this frame); a patch
// read ahead that the summaries say is absent becomes known absent, as the streamer's does.
//
// Frames are the fake's clock: beginFrame() ... acquire()s ... endFrame(). The summaries
// come from a function, or from a real pyramid's patch infos read once up front
// (fromPyramid), so the LOD sees the bounds and errors the builder wrote.
#pragma once

#include "terrain/pyramid/NativeTiles.h"
#include "terrain/pyramid/PatchIdHash.h"
#include "terrain/pyramid/PatchRecord.h"
#include "terrain/pyramid/PyramidLayout.h"
#include "terrain/pyramid/PyramidReader.h"
#include "terrain/runtime/TileResidency.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace terrain::test {

struct FakeTileResidencyOptions {
    int capacity = 256;  ///< layers: patches resident at once
    /// Frames from the first request to the frame in which the patch may become resident:
    /// 0 resident at once, 1 the next frame, ...
    int framesToArrive = 1;
    /// At most this many patches become resident per frame (the upload budget).
    int arrivalsPerFrame = std::numeric_limits<int>::max();
    /// Ids whose load fails: they are reported failed when they would have arrived.
    std::function<bool(const io::PatchId&)> fails = {};
    /// Whether prefetch() starts a load (as TileStreamer's reads one into its CPU cache): it
    /// then counts from the prefetch, and is dropped at a frame's end unless prefetched or
    /// acquired again in that frame (as the streamer cancels what no one wants).
    bool honourPrefetch = false;
    /// What every resident patch reports as its samples' steepest rises
    /// (TileResidency::residentSampleRises); none: the LOD bounds the sag alone.
    std::optional<io::SampleRises> sampleRises = std::nullopt;
};

class FakeTileResidency final : public runtime::TileResidency {
public:
    using InfoOf = std::function<io::PatchInfo(const io::PatchId&)>;

    FakeTileResidency(io::PyramidLayout layout, InfoOf infoOf, FakeTileResidencyOptions options)
        : m_layout(std::move(layout)), m_infoOf(std::move(infoOf)), m_options(std::move(options)) {
        m_layers.assign(static_cast<std::size_t>(m_options.capacity), Layer{});
    }

    /// Every patch summary of the pyramid at `path`, read once here (no I/O later).
    static std::unique_ptr<FakeTileResidency> fromPyramid(const std::filesystem::path& path,
                                                          FakeTileResidencyOptions options) {
        auto reader = io::PyramidReader::open(path);
        EXPECT_TRUE(reader) << reader.error().message;
        if (!reader) return nullptr;
        const io::PyramidLayout layout = reader.value().layout();
        auto infos =
            std::make_shared<std::unordered_map<io::PatchId, io::PatchInfo, io::PatchIdHash>>();
        for (int level = 0; level < layout.levelCount(); ++level) {
            for (std::int64_t y = 0; y < layout.patchesY(level); ++y) {
                for (std::int64_t x = 0; x < layout.patchesX(level); ++x) {
                    const io::PatchId id{level, x, y};
                    auto info = reader.value().patchInfo(id);
                    EXPECT_TRUE(info) << info.error().message;
                    if (info) (*infos)[id] = info.value();
                }
            }
        }
        return std::make_unique<FakeTileResidency>(
            layout, [infos](const io::PatchId& id) { return infos->at(id); }, std::move(options));
    }

    const io::PyramidLayout& layout() const { return m_layout; }

    /// Starts a frame: a patch asked for framesToArrive frames ago or more becomes resident
    /// when acquire() asks for it again (at most arrivalsPerFrame this frame), or fails.
    void beginFrame() {
        ++m_frame;
        m_arrivalsThisFrame = 0;
        // A read ahead of a patch the pyramid does not store ends known absent (as
        // TileStreamer's does), when it would have arrived.
        std::erase_if(m_prefetched, [&](const auto& p) {
            if (p.second.arrival > m_frame || m_infoOf(p.first).present) return false;
            m_absent.insert(p.first);
            return true;
        });
    }
    /// Ends the frame: acquired requests live until they arrive; prefetches not asked for
    /// again this frame are dropped.
    void endFrame() {
        std::erase_if(m_prefetched, [&](const auto& p) { return p.second.lastAsked != m_frame; });
    }

    // TileResidency -------------------------------------------------------------------------
    const io::PatchInfo* acquire(const io::PatchId& id, float priority) override {
        EXPECT_TRUE(io::isNativeTile(id) || m_layout.contains(id));
        EXPECT_GE(priority, 0.0f);
        if (const auto resident = m_resident.find(id); resident != m_resident.end()) {
            m_layers[static_cast<std::size_t>(resident->second)].lastUsedFrame = m_frame;
            return &m_layers[static_cast<std::size_t>(resident->second)].info;
        }
        if (m_failed.contains(id)) return nullptr;
        if (!m_infoOf(id).present) ++m_absentAcquires;
        auto pending = m_pending.find(id);
        if (pending == m_pending.end()) {
            std::uint64_t arrival = m_frame + static_cast<std::uint64_t>(m_options.framesToArrive);
            if (const auto ahead = m_prefetched.find(id); ahead != m_prefetched.end()) {
                arrival = ahead->second.arrival;  // on its way since its prefetch
                m_prefetched.erase(ahead);
            } else {
                ++m_requests;
            }
            pending = m_pending.emplace(id, arrival).first;
        }
        if (pending->second > m_frame || m_arrivalsThisFrame >= m_options.arrivalsPerFrame) {
            return nullptr;
        }
        if (m_options.fails && m_options.fails(id)) {
            m_pending.erase(pending);
            m_failed.insert(id);
            return nullptr;
        }
        const std::optional<int> layer = takeLayer();
        if (!layer) return nullptr;  // every layer pinned or used this frame: later
        m_pending.erase(pending);
        ++m_arrivalsThisFrame;
        Layer& l = m_layers[static_cast<std::size_t>(*layer)];
        l = {.id = id,
             .info = m_infoOf(id),
             .used = true,
             .pinned = false,
             .lastUsedFrame = m_frame};
        m_resident[id] = *layer;
        return &l.info;
    }
    void prefetch(const io::PatchId& id, float priority) override {
        EXPECT_TRUE(io::isNativeTile(id) || m_layout.contains(id));
        EXPECT_GE(priority, 0.0f);
        ++m_prefetchCalls;
        if (!m_options.honourPrefetch || m_resident.contains(id) || m_failed.contains(id) ||
            m_pending.contains(id) || m_absent.contains(id))
            return;
        auto [ahead, started] = m_prefetched.try_emplace(
            id, Prefetch{m_frame + static_cast<std::uint64_t>(m_options.framesToArrive), 0});
        if (started) ++m_requests;
        ahead->second.lastAsked = m_frame;
    }
    int layerOf(const io::PatchId& id) const override {
        const auto resident = m_resident.find(id);
        EXPECT_NE(resident, m_resident.end()) << "layerOf a patch that is not resident";
        return resident == m_resident.end() ? -1 : resident->second;
    }
    bool hasFailed(const io::PatchId& id) const override { return m_failed.contains(id); }
    bool knownAbsent(const io::PatchId& id) const override { return m_absent.contains(id); }
    void pin(const io::PatchId& id) override {
        Layer* l = layerOfResident(id);
        EXPECT_TRUE(l != nullptr && !l->pinned) << "pin of a patch not resident, or pinned";
        if (l != nullptr) l->pinned = true;
    }
    void unpin(const io::PatchId& id) override {
        Layer* l = layerOfResident(id);
        EXPECT_TRUE(l != nullptr && l->pinned) << "unpin of a patch not pinned";
        if (l == nullptr) return;
        l->pinned = false;
        l->lastUsedFrame = m_frame;  // the most recently used, as GpuTilePool::unpin
    }
    int capacity() const override { return m_options.capacity; }
    const io::PatchInfo* residentInfo(const io::PatchId& id) const override {
        const auto resident = m_resident.find(id);
        return resident == m_resident.end()
                   ? nullptr
                   : &m_layers[static_cast<std::size_t>(resident->second)].info;
    }
    bool isPinned(const io::PatchId& id) const override {
        const auto resident = m_resident.find(id);
        return resident != m_resident.end() &&
               m_layers[static_cast<std::size_t>(resident->second)].pinned;
    }
    std::optional<io::SampleRises> residentSampleRises(const io::PatchId& id) const override {
        return m_resident.contains(id) ? m_options.sampleRises : std::nullopt;
    }

    // For tests -----------------------------------------------------------------------------
    std::uint64_t requests() const { return m_requests; }  ///< distinct loads asked for
    std::size_t pending() const { return m_pending.size(); }  ///< acquired, not yet arrived
    std::uint64_t prefetchCalls() const { return m_prefetchCalls; }
    /// Patches read ahead and found absent (knownAbsent).
    std::size_t knownAbsentCount() const { return m_absent.size(); }
    /// Acquires of patches the pyramid does not store (the LOD must ask only for stored ones).
    std::uint64_t absentAcquires() const { return m_absentAcquires; }
    std::size_t pinnedCount() const {
        std::size_t n = 0;
        for (const Layer& l : m_layers) n += l.used && l.pinned ? 1 : 0;
        return n;
    }
    std::uint64_t evictions() const { return m_evictions; }
    const std::unordered_set<io::PatchId, io::PatchIdHash>& failed() const { return m_failed; }

private:
    struct Layer {
        io::PatchId id;
        io::PatchInfo info;
        bool used = false;
        bool pinned = false;
        std::uint64_t lastUsedFrame = 0;
    };

    Layer* layerOfResident(const io::PatchId& id) {
        const auto resident = m_resident.find(id);
        return resident == m_resident.end() ? nullptr
                                            : &m_layers[static_cast<std::size_t>(resident->second)];
    }

    // A free layer, else the least recently used one neither pinned nor used this frame.
    std::optional<int> takeLayer() {
        int victim = -1;
        for (int i = 0; i < m_options.capacity; ++i) {
            const Layer& l = m_layers[static_cast<std::size_t>(i)];
            if (!l.used) return i;
            if (l.pinned || l.lastUsedFrame == m_frame) continue;
            if (victim < 0 ||
                l.lastUsedFrame < m_layers[static_cast<std::size_t>(victim)].lastUsedFrame) {
                victim = i;
            }
        }
        if (victim < 0) return std::nullopt;
        m_resident.erase(m_layers[static_cast<std::size_t>(victim)].id);
        m_layers[static_cast<std::size_t>(victim)].used = false;
        ++m_evictions;
        return victim;
    }

    io::PyramidLayout m_layout;
    InfoOf m_infoOf;
    FakeTileResidencyOptions m_options;
    std::vector<Layer> m_layers;
    std::unordered_map<io::PatchId, int, io::PatchIdHash> m_resident;
    std::unordered_map<io::PatchId, std::uint64_t, io::PatchIdHash> m_pending;  // → arrival frame
    std::unordered_set<io::PatchId, io::PatchIdHash> m_failed;
    std::unordered_set<io::PatchId, io::PatchIdHash> m_absent;
    std::uint64_t m_absentAcquires = 0;
    struct Prefetch {
        std::uint64_t arrival = 0;
        std::uint64_t lastAsked = 0;
    };
    std::unordered_map<io::PatchId, Prefetch, io::PatchIdHash> m_prefetched;
    std::uint64_t m_prefetchCalls = 0;
    std::uint64_t m_frame = 0;
    std::uint64_t m_requests = 0;
    std::uint64_t m_evictions = 0;
    int m_arrivalsThisFrame = 0;
};

}  // namespace terrain::test
