// OpenEXR headers of a shard file and their check on reading (see ShardFormat.h).
#include "ShardFormat.h"

#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfIntAttribute.h>
#include <ImfLineOrder.h>
#include <ImfPartType.h>
#include <ImfTileDescription.h>
#include <ImfVecAttribute.h>
#include <fmt/format.h>

namespace terrain::io::shard {
namespace {

Imath::Box2i box(int width, int height) {
    return Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(width - 1, height - 1));
}

const char* pixelTypeName(Imf::PixelType type) {
    switch (type) {
        case Imf::UINT:
            return "UINT";
        case Imf::HALF:
            return "HALF";
        case Imf::FLOAT:
            return "FLOAT";
        default:
            return "unknown";
    }
}

std::string channelsText(const Imf::ChannelList& channels) {
    std::string text;
    for (auto it = channels.begin(); it != channels.end(); ++it)
        text += fmt::format("{}{} {}", text.empty() ? "" : ", ", it.name(),
                            pixelTypeName(it.channel().type));
    return text.empty() ? "none" : text;
}

template <typename Attribute>
const Attribute* findAttribute(const Imf::Header& h, const char* name) {
    return h.findTypedAttribute<Attribute>(name);
}

}  // namespace

std::uint32_t storedPresent(const PatchInfo& info) {
    return info.present ? 1U + 2U * info.presentChildren : 0U;
}

StoredInfo toStored(const PatchInfo& info, std::uint32_t heightDivisor) {
    return {storedPresent(info), info.minHeight,     info.maxHeight, info.error,   info.approxError,
            info.quantError,     info.noDataSamples, info.crc32,     heightDivisor};
}

PatchInfo fromStored(const StoredInfo& s) {
    return {s.present != 0,  s.minHeight,   s.maxHeight,
            s.error,         s.approxError, s.quantError,
            s.noDataSamples, s.crc32,       static_cast<std::uint8_t>(s.present >> 1)};
}

Imf::DeepFrameBuffer payloadFrame(unsigned int& count, char*& samples) {
    Imf::DeepFrameBuffer frame;
    frame.insertSampleCountSlice(
        Imf::Slice(Imf::UINT, reinterpret_cast<char*>(&count), 0, 0, 1, 1, 0.0, true, true));
    frame.insert(kPayloadChannel, Imf::DeepSlice(Imf::UINT, reinterpret_cast<char*>(&samples), 0, 0,
                                                 sizeof(std::uint32_t), 1, 1, 0.0, true, true));
    return frame;
}

std::vector<Imf::Header> shardHeaders(const PyramidLayout& layout, const ShardId& s, bool withMask,
                                      int compressionLevel) {
    const int cx = layout.shardCountX(s);
    const int cy = layout.shardCountY(s);
    // One pixel per patch in both parts (OpenEXR requires the parts of a multi-part file to
    // share their display window).
    const Imath::Box2i window = box(cx, cy);

    const auto makeHeader = [&](const char* name, const std::string& type, int tileW, int tileH,
                                Imf::Compression compression) {
        Imf::Header h(window, window);
        h.setName(name);
        h.setType(type);
        h.setTileDescription(Imf::TileDescription(static_cast<unsigned>(tileW),
                                                  static_cast<unsigned>(tileH), Imf::ONE_LEVEL));
        h.compression() = compression;
        h.lineOrder() = Imf::RANDOM_Y;
        h.insert(kFormatVersionAttribute, Imf::IntAttribute(kFormatVersion));
        h.insert(kLevelAttribute, Imf::IntAttribute(s.level));
        h.insert(kShardAttribute,
                 Imf::V2iAttribute(Imath::V2i(static_cast<int>(s.x), static_cast<int>(s.y))));
        return h;
    };

    std::vector<Imf::Header> headers;
    // The payloads are compressed already (PatchPayload.h): OpenEXR stores them as they are.
    headers.push_back(makeHeader(kPatchesPart, Imf::DEEPTILE, 1, 1, Imf::NO_COMPRESSION));
    headers.back().channels().insert(kPayloadChannel, Imf::Channel(Imf::UINT));
    headers.back().insert(kTileSamplesAttribute, Imf::IntAttribute(layout.tileSamples()));
    headers.back().insert(kBlocksPerSideAttribute, Imf::IntAttribute(layout.blocksPerSide()));
    headers.back().insert(kMaskAttribute, Imf::IntAttribute(withMask ? 1 : 0));

    headers.push_back(
        makeHeader(kPatchInfoPart, Imf::TILEDIMAGE, cx, cy,
                   compressionLevel == 0 ? Imf::NO_COMPRESSION : Imf::ZIP_COMPRESSION));
    Imf::ChannelList& info = headers.back().channels();
    info.insert("present", Imf::Channel(Imf::UINT));
    info.insert("minHeight", Imf::Channel(Imf::FLOAT));
    info.insert("maxHeight", Imf::Channel(Imf::FLOAT));
    info.insert("error", Imf::Channel(Imf::FLOAT));
    info.insert("approxError", Imf::Channel(Imf::FLOAT));
    info.insert("quantError", Imf::Channel(Imf::FLOAT));
    info.insert("noDataSamples", Imf::Channel(Imf::UINT));
    info.insert("crc32", Imf::Channel(Imf::UINT));
    info.insert("heightDivisor", Imf::Channel(Imf::UINT));
    return headers;
}

Status checkPartHeader(const Imf::Header& actual, const Imf::Header& expected) {
    const std::string part = expected.name();
    if (!actual.hasType() || actual.type() != expected.type())
        return Error{
            fmt::format("part '{}' is not a {}", part,
                        expected.type() == Imf::DEEPTILE ? "deep tiled part" : "tiled image")};
    const Imf::TileDescription& t = actual.tileDescription();
    const Imf::TileDescription& e = expected.tileDescription();
    if (t.xSize != e.xSize || t.ySize != e.ySize || t.mode != Imf::ONE_LEVEL)
        return Error{fmt::format(
            "part '{}' has {} × {} tiles{}, expected {} × {} (one level)", part, t.xSize, t.ySize,
            t.mode == Imf::ONE_LEVEL ? "" : " with mipmap levels", e.xSize, e.ySize)};
    const Imath::Box2i& d = actual.dataWindow();
    const Imath::Box2i& ed = expected.dataWindow();
    if (d != ed)
        return Error{fmt::format(
            "part '{}' has data window ({}, {}) – ({}, {}), expected ({}, "
            "{}) – ({}, {})",
            part, d.min.x, d.min.y, d.max.x, d.max.y, ed.min.x, ed.min.y, ed.max.x, ed.max.y)};
    const Imf::ChannelList& c = actual.channels();
    const Imf::ChannelList& ec = expected.channels();
    bool same = true;
    for (auto it = ec.begin(); it != ec.end(); ++it) {
        const Imf::Channel* found = c.findChannel(it.name());
        same = same && found != nullptr && found->type == it.channel().type &&
               found->xSampling == 1 && found->ySampling == 1;
    }
    for (auto it = c.begin(); it != c.end(); ++it) same = same && ec.findChannel(it.name());
    if (!same)
        return Error{fmt::format("part '{}' has channels {}, expected {}", part, channelsText(c),
                                 channelsText(ec))};
    const auto* version = findAttribute<Imf::IntAttribute>(actual, kFormatVersionAttribute);
    if (version == nullptr || version->value() != kFormatVersion)
        return Error{fmt::format("part '{}' has {} {}, expected {}", part, kFormatVersionAttribute,
                                 version ? std::to_string(version->value()) : "missing",
                                 kFormatVersion)};
    for (const char* name : {kTileSamplesAttribute, kBlocksPerSideAttribute, kMaskAttribute}) {
        const auto* want = findAttribute<Imf::IntAttribute>(expected, name);
        if (want == nullptr) continue;  // not an attribute of this part
        const auto* have = findAttribute<Imf::IntAttribute>(actual, name);
        if (have == nullptr || have->value() != want->value())
            return Error{fmt::format("part '{}' has {} {}, expected {}", part, name,
                                     have ? std::to_string(have->value()) : "missing",
                                     want->value())};
    }
    const auto* level = findAttribute<Imf::IntAttribute>(actual, kLevelAttribute);
    const auto* shard = findAttribute<Imf::V2iAttribute>(actual, kShardAttribute);
    const auto* eLevel = findAttribute<Imf::IntAttribute>(expected, kLevelAttribute);
    const auto* eShard = findAttribute<Imf::V2iAttribute>(expected, kShardAttribute);
    if (level == nullptr || shard == nullptr || level->value() != eLevel->value() ||
        shard->value() != eShard->value())
        return Error{fmt::format("part '{}' says it is {}, expected level {} shard ({}, {})", part,
                                 level && shard
                                     ? fmt::format("level {} shard ({}, {})", level->value(),
                                                   shard->value().x, shard->value().y)
                                     : std::string("of no level/shard"),
                                 eLevel->value(), eShard->value().x, eShard->value().y)};
    return {};
}

}  // namespace terrain::io::shard
