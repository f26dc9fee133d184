// manifest.json of a pyramid (docs/pyramid-format.md): JSON through nlohmann, every field
// checked on the way in so a damaged or foreign manifest is an Error that names the field.
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/pyramid/VirtualPlanetPyramid.h"
#include "terrain/remote/RemoteFiles.h"

#include "terrain/base/AtomicFile.h"
#include "terrain/pyramid/GlobeLayout.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

namespace terrain::io {
namespace {

using Json = nlohmann::ordered_json;

// A field that is missing or of the wrong type; turned into an Error at the API boundary.
struct FieldError {
    std::string field;
    std::string expected;
};

std::string join(const std::string& parent, std::string_view key) {
    return parent.empty() ? std::string(key) : fmt::format("{}.{}", parent, key);
}

const Json& member(const Json& object, const std::string& parent, std::string_view key) {
    const auto it = object.find(key);
    if (it == object.end()) throw FieldError{join(parent, key), "present"};
    return *it;
}

const Json& objectField(const Json& object, const std::string& parent, std::string_view key) {
    const Json& value = member(object, parent, key);
    if (!value.is_object()) throw FieldError{join(parent, key), "an object"};
    return value;
}

const Json& arrayField(const Json& object, const std::string& parent, std::string_view key) {
    const Json& value = member(object, parent, key);
    if (!value.is_array()) throw FieldError{join(parent, key), "an array"};
    return value;
}

std::int64_t int64Field(const Json& object, const std::string& parent, std::string_view key) {
    const Json& value = member(object, parent, key);
    if (value.is_number_unsigned()) {
        const auto u = value.get<std::uint64_t>();
        if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
            throw FieldError{join(parent, key), "a 64-bit integer"};
        return static_cast<std::int64_t>(u);
    }
    if (!value.is_number_integer()) throw FieldError{join(parent, key), "an integer"};
    return value.get<std::int64_t>();
}

int intField(const Json& object, const std::string& parent, std::string_view key) {
    const std::int64_t v = int64Field(object, parent, key);
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
        throw FieldError{join(parent, key), "a 32-bit integer"};
    return static_cast<int>(v);
}

double numberField(const Json& object, const std::string& parent, std::string_view key) {
    const Json& value = member(object, parent, key);
    if (!value.is_number()) throw FieldError{join(parent, key), "a number"};
    return value.get<double>();
}

std::optional<double> optionalNumberField(const Json& object, const std::string& parent,
                                          std::string_view key) {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    if (!it->is_number()) throw FieldError{join(parent, key), "a number or null"};
    return it->get<double>();
}

bool boolField(const Json& object, const std::string& parent, std::string_view key) {
    const Json& value = member(object, parent, key);
    if (!value.is_boolean()) throw FieldError{join(parent, key), "true or false"};
    return value.get<bool>();
}

std::string stringField(const Json& object, const std::string& parent, std::string_view key) {
    const Json& value = member(object, parent, key);
    if (!value.is_string()) throw FieldError{join(parent, key), "a string"};
    return value.get<std::string>();
}

CrsKind crsKindFromName(const std::string& name, const std::string& field) {
    for (CrsKind kind : {CrsKind::Unknown, CrsKind::Projected, CrsKind::Geographic})
        if (name == crsKindName(kind)) return kind;
    throw FieldError{field, "\"projected\", \"geographic\" or \"unknown\""};
}

Json georeferenceJson(const PyramidManifest& m) {
    const Georeference& g = m.georeference;
    Json j;
    j["crsKind"] = crsKindName(g.crsKind);
    j["epsg"] = g.epsg == Georeference::kUnknownProjectedCrs ? Json(nullptr) : Json(g.epsg);
    j["wkt"] = g.wkt;
    j["originX"] = g.originX;
    j["originY"] = g.originY;
    j["pixelSizeX"] = g.pixelSizeX;
    j["pixelSizeY"] = g.pixelSizeY;
    j["verticalScale"] = m.vertical.scale;
    j["verticalOffset"] = m.vertical.offset;
    j["verticalUnits"] = PyramidManifest::kVerticalUnits;
    return j;
}

void readGeoreference(const Json& root, PyramidManifest& m) {
    const std::string p = "georeference";
    const Json& j = objectField(root, "", p);
    Georeference& g = m.georeference;
    g.crsKind = crsKindFromName(stringField(j, p, "crsKind"), join(p, "crsKind"));
    const Json& epsg = member(j, p, "epsg");
    g.epsg = epsg.is_null() ? Georeference::kUnknownProjectedCrs : intField(j, p, "epsg");
    g.wkt = stringField(j, p, "wkt");
    g.originX = numberField(j, p, "originX");
    g.originY = numberField(j, p, "originY");
    g.pixelSizeX = numberField(j, p, "pixelSizeX");
    g.pixelSizeY = numberField(j, p, "pixelSizeY");
    m.vertical.scale = numberField(j, p, "verticalScale");
    m.vertical.offset = numberField(j, p, "verticalOffset");
    if (stringField(j, p, "verticalUnits") != PyramidManifest::kVerticalUnits)
        throw FieldError{join(p, "verticalUnits"), "\"metre\""};
}

// The layout fields as written; PyramidLayout::create checks them afterwards.
struct LayoutFields {
    int patchSamples = 0, apronSamples = 0, blockQuads = 0, shardPatches = 0, finestLevel = 0;
    std::int64_t rasterWidth = 0, rasterHeight = 0;
};

PyramidManifest parseFields(const Json& root, LayoutFields& f) {
    PyramidManifest m;
    m.formatVersion = intField(root, "", "formatVersion");
    f.patchSamples = intField(root, "", "patchSamples");
    f.apronSamples = intField(root, "", "apronSamples");
    f.blockQuads = intField(root, "", "blockQuads");
    f.shardPatches = intField(root, "", "shardPatches");
    f.finestLevel = intField(root, "", "finestLevel");
    const Json& raster = objectField(root, "", "raster");
    f.rasterWidth = int64Field(raster, "raster", "width");
    f.rasterHeight = int64Field(raster, "raster", "height");
    readGeoreference(root, m);

    const Json& noData = objectField(root, "", "noData");
    m.noData.present = boolField(noData, "noData", "present");
    m.noData.sourceValue = optionalNumberField(noData, "noData", "sourceValue");
    m.noData.samples = int64Field(noData, "noData", "samples");
    m.noData.fill = stringField(noData, "noData", "fill");
    if (noData.contains("sources")) {  // since the void fill
        for (const Json& source : arrayField(noData, "noData", "sources")) {
            ManifestSourceNoData entry;
            entry.input = stringField(source, "noData.sources", "input");
            entry.sourceValueRecorded = source.contains("sourceValue");  // since issue 52
            entry.sourceValue = optionalNumberField(source, "noData.sources", "sourceValue");
            entry.samples = int64Field(source, "noData.sources", "samples");
            entry.overBeneath = int64Field(source, "noData.sources", "overBeneath");
            m.noData.sources.push_back(std::move(entry));
        }
    }

    const Json& stats = objectField(root, "", "statistics");
    m.statistics.minHeight = numberField(stats, "statistics", "minHeight");
    m.statistics.maxHeight = numberField(stats, "statistics", "maxHeight");
    m.statistics.validSamples = int64Field(stats, "statistics", "validSamples");
    m.statistics.rootError = numberField(stats, "statistics", "rootError");

    const Json& levels = arrayField(root, "", "levels");
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const std::string p = fmt::format("levels[{}]", i);
        if (!levels[i].is_object()) throw FieldError{p, "an object"};
        const Json& l = levels[i];
        ManifestLevel level;
        level.level = intField(l, p, "level");
        level.patchesX = int64Field(l, p, "patchesX");
        level.patchesY = int64Field(l, p, "patchesY");
        level.presentPatches = int64Field(l, p, "presentPatches");
        level.shardsX = int64Field(l, p, "shardsX");
        level.shardsY = int64Field(l, p, "shardsY");
        level.sampleStep = int64Field(l, p, "sampleStep");
        level.maxError = numberField(l, p, "maxError");
        if (m.formatVersion == PyramidManifest::kGlobeFormatVersion) {
            const Json& shards = arrayField(l, p, "presentShards");
            for (std::size_t s = 0; s < shards.size(); ++s) {
                const std::string sp = fmt::format("{}.presentShards[{}]", p, s);
                const Json& pair = shards[s];
                if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number_integer() ||
                    !pair[1].is_number_integer())
                    throw FieldError{sp, "a pair of integers [sx, sy]"};
                level.presentShards.push_back(
                    {level.level, pair[0].get<std::int64_t>(), pair[1].get<std::int64_t>()});
            }
        }
        m.levels.push_back(level);
    }

    const Json& source = objectField(root, "", "source");
    const Json& inputs = arrayField(source, "source", "inputs");
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        if (!inputs[i].is_string())
            throw FieldError{fmt::format("source.inputs[{}]", i), "a string"};
        m.source.inputs.push_back(inputs[i].get<std::string>());
    }
    m.source.reader = stringField(source, "source", "reader");
    m.source.sampleType = stringField(source, "source", "sampleType");
    if (source.contains("band")) m.source.band = intField(source, "source", "band");
    if (source.contains("bandCount")) m.source.bandCount = intField(source, "source", "bandCount");
    if (m.source.band < 1 || m.source.band > m.source.bandCount)
        throw FieldError{"source.band", "a band from 1 to source.bandCount"};
    if (source.contains("rowsFlipped"))
        m.source.rowsFlipped = boolField(source, "source", "rowsFlipped");
    if (source.contains("columnsFlipped"))
        m.source.columnsFlipped = boolField(source, "source", "columnsFlipped");
    if (source.contains("resampled")) {
        const Json& r = objectField(source, "source", "resampled");
        const std::string p = "source.resampled";
        ManifestResampling& resampled = m.source.resampled.emplace();
        resampled.method = stringField(r, p, "method");
        resampled.width = int64Field(r, p, "width");
        resampled.height = int64Field(r, p, "height");
        const Json& gt = arrayField(r, p, "geoTransform");
        if (gt.size() != 6) throw FieldError{p + ".geoTransform", "6 numbers"};
        for (std::size_t i = 0; i < 6; ++i) {
            if (!gt[i].is_number()) throw FieldError{p + ".geoTransform", "6 numbers"};
            resampled.geoTransform[i] = gt[i].get<double>();
        }
        resampled.validSamples = int64Field(r, p, "validSamples");
        resampled.finestDistanceM = numberField(r, p, "finestDistanceM");
    }

    if (root.contains("quantization")) {
        const Json& q = objectField(root, "", "quantization");
        const std::string p = "quantization";
        if (stringField(q, p, "rule") != ManifestQuantization::kRule)
            throw FieldError{p + ".rule", fmt::format("\"{}\"", ManifestQuantization::kRule)};
        ManifestQuantization& quantization = m.quantization.emplace();
        quantization.maxErrorM = numberField(q, p, "maxErrorM");
        if (!(quantization.maxErrorM > 0.0) || !std::isfinite(quantization.maxErrorM))
            throw FieldError{p + ".maxErrorM", "a finite number of metres > 0"};
        quantization.finestLargestErrorM = numberField(q, p, "finestLargestErrorM");
    }

    if (root.contains("imagery")) {  // since imagery was draped (issue 47)
        for (const Json& entry : arrayField(root, "", "imagery")) {
            const std::string p = "imagery";
            ManifestImageryLayer layer;
            layer.name = stringField(entry, p, "name");
            layer.kind = stringField(entry, p, "kind");
            if (layer.kind != ManifestImageryLayer::kStoredKind &&
                layer.kind != ManifestImageryLayer::kPlanetKind)
                throw FieldError{p + ".kind", fmt::format("\"{}\" or \"{}\"",
                                                          ManifestImageryLayer::kStoredKind,
                                                          ManifestImageryLayer::kPlanetKind)};
            layer.folder = stringField(entry, p, "folder");
            layer.input = stringField(entry, p, "input");
            layer.codec = stringField(entry, p, "codec");
            layer.coarsestLevel = intField(entry, p, "coarsestLevel");
            layer.finestLevel = intField(entry, p, "finestLevel");
            layer.opacity = numberField(entry, p, "opacity");
            m.imagery.push_back(std::move(layer));
        }
    }

    const Json& build = objectField(root, "", "build");
    m.build.tool = stringField(build, "build", "tool");
    m.build.version = stringField(build, "build", "version");
    m.build.seconds = numberField(build, "build", "seconds");

    if (m.formatVersion == PyramidManifest::kGlobeFormatVersion) {
        const Json& globe = objectField(root, "", "globe");
        if (stringField(globe, "globe", "tiling") != ManifestGlobe::kTiling)
            throw FieldError{"globe.tiling", fmt::format("\"{}\"", ManifestGlobe::kTiling)};
        if (intField(globe, "globe", "levelOffset") != ManifestGlobe::kLevelOffset)
            throw FieldError{"globe.levelOffset", std::to_string(ManifestGlobe::kLevelOffset)};
        const Json& extent = arrayField(globe, "globe", "sourceExtent");
        if (extent.size() != 4 ||
            !std::all_of(extent.begin(), extent.end(), [](const Json& v) { return v.is_number(); }))
            throw FieldError{"globe.sourceExtent", "[west, south, east, north] in degrees"};
        m.globe = ManifestGlobe{
            .faceFinestLevel = intField(globe, "globe", "faceFinestLevel"),
            .west = extent[0].get<double>(),
            .south = extent[1].get<double>(),
            .east = extent[2].get<double>(),
            .north = extent[3].get<double>(),
            .seams = {},
            .sources = {},
            .seaLevelM = optionalNumberField(globe, "globe", "seaLevelM").value_or(0.0)};
        if (!std::isfinite(m.globe->seaLevelM))
            throw FieldError{"globe.seaLevelM", "a finite number of metres"};
        if (globe.contains("oversampleLevels")) {  // since terrain-build --oversample-levels
            m.globe->oversampleLevels = intField(globe, "globe", "oversampleLevels");
            if (m.globe->oversampleLevels < 0 ||
                m.globe->oversampleLevels > m.globe->faceFinestLevel)
                throw FieldError{"globe.oversampleLevels",
                                 "0 to the finest face level (face levels below the sources)"};
        }
        if (globe.contains("sources")) {  // since each source's extent was recorded
            for (const Json& entry : arrayField(globe, "globe", "sources")) {
                ManifestGlobeSource s;
                s.input = stringField(entry, "globe.sources", "input");
                const Json& box = arrayField(entry, "globe.sources", "extent");
                if (box.size() != 4 || !std::all_of(box.begin(), box.end(),
                                                    [](const Json& v) { return v.is_number(); }))
                    throw FieldError{"globe.sources.extent",
                                     "[west, south, east, north] in degrees"};
                s.west = box[0].get<double>();
                s.south = box[1].get<double>();
                s.east = box[2].get<double>();
                s.north = box[3].get<double>();
                if (entry.contains("native"))  // since terrain-build --native-leaves
                    s.native = stringField(entry, "globe.sources", "native");
                m.globe->sources.push_back(std::move(s));
            }
        }
        if (globe.contains("seams")) {  // since the band followed the step
            for (const Json& seam : arrayField(globe, "globe", "seams")) {
                ManifestSeam s;
                s.input = stringField(seam, "globe.seams", "input");
                s.seamSlope = numberField(seam, "globe.seams", "seamSlope");
                s.sourceSlopeP99 = numberField(seam, "globe.seams", "sourceSlopeP99");
                s.bandScaleRatio = numberField(seam, "globe.seams", "bandScaleRatio");
                s.largestStepM = numberField(seam, "globe.seams", "largestStepM");
                for (const auto& [key, pair] : {std::pair{"bandPixels", &s.bandPixels},
                                                std::pair{"bandMetres", &s.bandMetres}}) {
                    const Json& range = arrayField(seam, "globe.seams", key);
                    if (range.size() != 2 || !range[0].is_number() || !range[1].is_number())
                        throw FieldError{fmt::format("globe.seams.{}", key), "[narrowest, widest]"};
                    *pair = {range[0].get<double>(), range[1].get<double>()};
                }
                s.cappedPixels = int64Field(seam, "globe.seams", "cappedPixels");
                m.globe->seams.push_back(std::move(s));
            }
        }
    }
    // Written before each source's value was: a pyramid of one source (a plane's, mosaic or
    // not, or a globe of one input) declared the pyramid's.
    if (!m.globe || m.source.inputs.size() == 1)
        for (ManifestSourceNoData& entry : m.noData.sources)
            if (!entry.sourceValueRecorded) {
                entry.sourceValue = m.noData.sourceValue;
                entry.sourceValueRecorded = true;
            }
    return m;
}

// What describes the raster's layout in words, for messages.
std::string layoutText(const PyramidLayout& layout) {
    return fmt::format("a {} × {} raster in patches of {} samples and shards of {} patches",
                       layout.rasterWidth(), layout.rasterHeight(), layout.patchSamples(),
                       layout.shardPatches());
}

// Everything that must hold between the fields, with the reason in the message.
Status checkGlobe(const PyramidManifest& m, const std::string& name) {
    const int expectedVersion =
        m.globe ? PyramidManifest::kGlobeFormatVersion : PyramidManifest::kFormatVersion;
    if (m.formatVersion != expectedVersion)
        return Error{fmt::format("{}: formatVersion is {}, but a {} pyramid is version {}", name,
                                 m.formatVersion, m.globe ? "globe" : "planar", expectedVersion)};
    if (!m.globe) {
        for (const ManifestLevel& level : m.levels)
            if (!level.presentShards.empty())
                return Error{
                    fmt::format("{}: levels[{}] lists present shards, which only a "
                                "globe pyramid has",
                                name, level.level)};
        return {};
    }
    const int faceLevel = m.globe->faceFinestLevel;
    const Result<PyramidLayout> expected = globeLayout(
        faceLevel, m.layout.patchSamples(), m.layout.blockQuads(), m.layout.shardPatches());
    if (!expected) return Error{fmt::format("{}: globe: {}", name, expected.error().message)};
    if (!(expected.value() == m.layout))
        return Error{
            fmt::format("{}: globe: faceFinestLevel {} needs a {} × {} raster, not {} × {}", name,
                        faceLevel, expected.value().rasterWidth(), expected.value().rasterHeight(),
                        m.layout.rasterWidth(), m.layout.rasterHeight())};
    if (m.georeference.crsKind != CrsKind::Geographic)
        return Error{fmt::format("{}: globe: the georeference must be geographic, not {}", name,
                                 crsKindName(m.georeference.crsKind))};
    for (const ManifestSeam& s : m.globe->seams) {
        const bool finite = std::isfinite(s.seamSlope) && std::isfinite(s.sourceSlopeP99) &&
                            std::isfinite(s.bandScaleRatio) && s.bandScaleRatio >= 0.0 &&
                            std::isfinite(s.largestStepM) && std::isfinite(s.bandPixels[1]) &&
                            std::isfinite(s.bandMetres[1]);
        if (!finite || s.seamSlope < 0.0 || s.sourceSlopeP99 < 0.0 || s.largestStepM < 0.0 ||
            s.bandPixels[0] < 0.0 || s.bandPixels[0] > s.bandPixels[1] || s.bandMetres[0] < 0.0 ||
            s.bandMetres[0] > s.bandMetres[1] || s.cappedPixels < 0)
            return Error{fmt::format(
                "{}: globe.seams: {} has seam slope {}, 99th-percentile slope {}, step {} m, "
                "band {}–{} px ({}–{} m), {} capped pixels: slopes, steps and widths are "
                "finite and ≥ 0, the narrowest no wider than the widest",
                name, s.input, s.seamSlope, s.sourceSlopeP99, s.largestStepM, s.bandPixels[0],
                s.bandPixels[1], s.bandMetres[0], s.bandMetres[1], s.cappedPixels)};
    }
    for (const ManifestGlobeSource& s : m.globe->sources)
        if (!(std::abs(s.west) <= 180.0 && std::abs(s.east) <= 180.0 && s.south >= -90.0 &&
              s.south <= s.north && s.north <= 90.0))
            return Error{fmt::format(
                "{}: globe.sources: {} has the extent [{}, {}, {}, {}]: west and east lie within "
                "-180 … 180, south and north within -90 … 90, south no further north than north",
                name, s.input, s.west, s.south, s.east, s.north)};
    for (const ManifestGlobeSource& s : m.globe->sources) {
        // A folder inside the pyramid, named by the writer: nothing a reader could be led out
        // of the pyramid by.
        const std::string_view prefix = ManifestGlobeSource::kNativeFolder;
        const std::string_view rest =
            std::string_view(s.native).substr(std::min(s.native.size(), prefix.size()));
        if (!s.native.empty() &&
            (!s.native.starts_with(prefix) || rest.empty() || rest.size() > 6 ||
             !std::all_of(rest.begin(), rest.end(), [](char c) { return c >= '0' && c <= '9'; })))
            return Error{
                fmt::format("{}: globe.sources: {} has the native grid \"{}\": it is "
                            "\"{}\" and a number",
                            name, s.input, s.native, prefix)};
    }
    for (const ManifestLevel& level : m.levels) {
        if (level.level < ManifestGlobe::kLevelOffset &&
            (level.presentPatches != 0 || !level.presentShards.empty()))
            return Error{fmt::format("{}: globe: level {} is above the faces and holds no patch",
                                     name, level.level)};
        for (std::size_t i = 0; i < level.presentShards.size(); ++i) {
            const ShardId& s = level.presentShards[i];
            if (s.x < 0 || s.y < 0 || s.x >= level.shardsX || s.y >= level.shardsY)
                return Error{
                    fmt::format("{}: levels[{}].presentShards[{}] = [{}, {}] is outside "
                                "the level's {} × {} shards",
                                name, level.level, i, s.x, s.y, level.shardsX, level.shardsY)};
            if (i > 0) {
                const ShardId& before = level.presentShards[i - 1];
                if (std::pair(before.y, before.x) >= std::pair(s.y, s.x))
                    return Error{
                        fmt::format("{}: levels[{}].presentShards is not sorted by "
                                    "(sy, sx) without repeats",
                                    name, level.level)};
            }
        }
    }
    return {};
}

// Imagery layers: unique names, levels from the pyramid's root down (at most the deepest a
// patch key holds), an opacity in 0 … 1, a folder inside the pyramid for stored tiles, and
// "planet" layers only on the virtual planet (which has no folder to read).
Status checkImagery(const PyramidManifest& m, const std::string& name) {
    const int rootLevel = m.globe ? ManifestGlobe::kLevelOffset : 0;
    // Imagery may be finer than the DEM, up to 2^16 times on the plane.
    const int deepest = m.globe ? ManifestGlobe::kLevelOffset + kMaxGlobeFaceLevel
                                : m.layout.finestLevel() + 16;
    for (std::size_t i = 0; i < m.imagery.size(); ++i) {
        const ManifestImageryLayer& l = m.imagery[i];
        const std::string at = fmt::format("{}: imagery[{}] (\"{}\")", name, i, l.name);
        if (l.name.empty()) return Error{at + ": a layer needs a name"};
        for (std::size_t j = 0; j < i; ++j)
            if (m.imagery[j].name == l.name)
                return Error{fmt::format("{}: the name is also imagery[{}]'s", at, j)};
        if (l.coarsestLevel != rootLevel || l.finestLevel < l.coarsestLevel ||
            l.finestLevel > deepest)
            return Error{fmt::format("{}: levels {} … {}: the first must be the root level {}, "
                                     "the last from it to {}",
                                     at, l.coarsestLevel, l.finestLevel, rootLevel, deepest)};
        if (!(l.opacity >= 0.0 && l.opacity <= 1.0))
            return Error{fmt::format("{}: opacity {} is outside 0 … 1", at, l.opacity)};
        if (l.kind == ManifestImageryLayer::kStoredKind) {
            const std::filesystem::path folder(l.folder);
            if (l.folder.empty() || folder.is_absolute() ||
                std::any_of(folder.begin(), folder.end(),
                            [](const std::filesystem::path& part) { return part == ".."; }))
                return Error{fmt::format("{}: folder \"{}\" must be a relative path inside "
                                         "the pyramid",
                                         at, l.folder)};
        } else if (!m.globe) {
            return Error{at + ": a \"planet\" layer belongs to the virtual planet"};
        }
    }
    return {};
}

Status checkManifest(const PyramidManifest& m, const std::string& name) {
    if (Status globe = checkGlobe(m, name); !globe) return globe;
    if (m.quantization &&
        (!(m.quantization->maxErrorM > 0.0) || !std::isfinite(m.quantization->maxErrorM)))
        return Error{
            fmt::format("{}: quantization.maxErrorM must be a finite number of metres "
                        "> 0, not {}",
                        name, m.quantization->maxErrorM)};
    if (Status imagery = checkImagery(m, name); !imagery) return imagery;
    // A layout is only made by PyramidLayout::create; one that create rejects is a default
    // (empty) one.
    const PyramidLayout& layout = m.layout;
    const Result<PyramidLayout> created =
        PyramidLayout::create(layout.rasterWidth(), layout.rasterHeight(), layout.patchSamples(),
                              layout.blockQuads(), layout.shardPatches());
    if (!created) return Error{fmt::format("{}: bad layout: {}", name, created.error().message)};
    const std::string what = layoutText(layout);
    if (std::ssize(m.levels) != layout.levelCount())
        return Error{fmt::format("{}: inconsistent layout: {} levels listed, but {} has {}", name,
                                 m.levels.size(), what, layout.levelCount())};
    for (int l = 0; l < layout.levelCount(); ++l) {
        const ManifestLevel& level = m.levels[static_cast<std::size_t>(l)];
        const auto mismatch = [&](std::string_view field, std::int64_t listed,
                                  std::int64_t expected) {
            return Error{fmt::format("{}: inconsistent layout: levels[{}].{} is {}, but {} has {}",
                                     name, l, field, listed, what, expected)};
        };
        if (level.level != l) return mismatch("level", level.level, l);
        if (level.patchesX != layout.patchesX(l))
            return mismatch("patchesX", level.patchesX, layout.patchesX(l));
        if (level.patchesY != layout.patchesY(l))
            return mismatch("patchesY", level.patchesY, layout.patchesY(l));
        if (level.shardsX != layout.shardsX(l))
            return mismatch("shardsX", level.shardsX, layout.shardsX(l));
        if (level.shardsY != layout.shardsY(l))
            return mismatch("shardsY", level.shardsY, layout.shardsY(l));
        if (level.sampleStep != layout.levelStep(l))
            return mismatch("sampleStep", level.sampleStep, layout.levelStep(l));
        if (level.presentPatches < 0 || level.presentPatches > layout.patchCount(l))
            return Error{fmt::format("{}: levels[{}].presentPatches is {}, outside 0 … {}", name, l,
                                     level.presentPatches, layout.patchCount(l))};
        if (!std::isfinite(level.maxError) || level.maxError < 0.0)
            return Error{fmt::format("{}: levels[{}].maxError is {}; an error bound is ≥ 0", name,
                                     l, level.maxError)};
    }
    const Georeference& g = m.georeference;
    if (!std::isfinite(g.originX) || !std::isfinite(g.originY) || !(g.pixelSizeX > 0.0) ||
        !(g.pixelSizeY > 0.0) || !std::isfinite(g.pixelSizeX) || !std::isfinite(g.pixelSizeY))
        return Error{
            fmt::format("{}: georeference: origin ({}, {}) and pixel size ({}, {}) must "
                        "be finite, pixel sizes > 0",
                        name, g.originX, g.originY, g.pixelSizeX, g.pixelSizeY)};
    if (!std::isfinite(m.vertical.scale) || m.vertical.scale == 0.0 ||
        !std::isfinite(m.vertical.offset))
        return Error{
            fmt::format("{}: georeference: verticalScale {} and verticalOffset {} must be "
                        "finite, the scale non-zero",
                        name, m.vertical.scale, m.vertical.offset)};
    if (m.noData.fill != ManifestNoData::kRowLinearFill &&
        m.noData.fill != ManifestNoData::kMembraneFill &&
        m.noData.fill != ManifestNoData::kDeltaSurfaceFill)
        return Error{fmt::format("{}: noData.fill is \"{}\"; known are \"{}\", \"{}\" and \"{}\"",
                                 name, m.noData.fill, ManifestNoData::kRowLinearFill,
                                 ManifestNoData::kMembraneFill, ManifestNoData::kDeltaSurfaceFill)};
    for (const ManifestSourceNoData& source : m.noData.sources)
        if (source.samples < 0 || source.overBeneath < 0 || source.overBeneath > source.samples)
            return Error{
                fmt::format("{}: noData.sources: {} has {} samples filled, {} over the "
                            "sources beneath",
                            name, source.input, source.samples, source.overBeneath)};
    const double rasterSamples =
        static_cast<double>(m.layout.rasterWidth()) * static_cast<double>(m.layout.rasterHeight());
    if (m.noData.samples < 0 || static_cast<double>(m.noData.samples) > rasterSamples)
        return Error{fmt::format("{}: noData.samples is {}, outside 0 … {} × {}", name,
                                 m.noData.samples, m.layout.rasterWidth(),
                                 m.layout.rasterHeight())};
    if (m.statistics.validSamples < 0 ||
        static_cast<double>(m.statistics.validSamples) > rasterSamples)
        return Error{fmt::format("{}: statistics.validSamples is {}, outside 0 … {} × {}", name,
                                 m.statistics.validSamples, m.layout.rasterWidth(),
                                 m.layout.rasterHeight())};
    if (!std::isfinite(m.statistics.rootError) || m.statistics.rootError < 0.0)
        return Error{fmt::format("{}: statistics.rootError is {}; an error bound is ≥ 0", name,
                                 m.statistics.rootError)};
    return {};
}

}  // namespace

double ManifestQuantization::halfStep(int level, int finestLevel) const {
    return std::ldexp(maxErrorM, finestLevel - level);
}

PyramidManifest PyramidManifest::forLayout(const PyramidLayout& layout) {
    PyramidManifest m;
    m.layout = layout;
    for (int l = 0; l < layout.levelCount(); ++l) {
        m.levels.push_back({.level = l,
                            .patchesX = layout.patchesX(l),
                            .patchesY = layout.patchesY(l),
                            .presentPatches = layout.patchCount(l),
                            .shardsX = layout.shardsX(l),
                            .shardsY = layout.shardsY(l),
                            .sampleStep = layout.levelStep(l),
                            .maxError = 0.0,
                            .presentShards = {}});
    }
    return m;
}

std::string toJson(const PyramidManifest& m) {
    Json j;
    j["format"] = PyramidManifest::kFormatName;
    j["formatVersion"] = m.formatVersion;
    j["patchSamples"] = m.layout.patchSamples();
    j["apronSamples"] = m.layout.apronSamples();
    j["blockQuads"] = m.layout.blockQuads();
    j["shardPatches"] = m.layout.shardPatches();
    j["finestLevel"] = m.layout.finestLevel();
    j["raster"] = {{"width", m.layout.rasterWidth()}, {"height", m.layout.rasterHeight()}};
    j["georeference"] = georeferenceJson(m);
    j["noData"] = {{"present", m.noData.present},
                   {"sourceValue", m.noData.sourceValue ? Json(*m.noData.sourceValue) : Json()},
                   {"samples", m.noData.samples},
                   {"fill", m.noData.fill}};
    if (!m.noData.sources.empty()) {
        Json sources = Json::array();
        for (const ManifestSourceNoData& source : m.noData.sources) {
            Json entry = {{"input", source.input}};
            if (source.sourceValueRecorded)
                entry["sourceValue"] = source.sourceValue ? Json(*source.sourceValue) : Json();
            entry["samples"] = source.samples;
            entry["overBeneath"] = source.overBeneath;
            sources.push_back(std::move(entry));
        }
        j["noData"]["sources"] = std::move(sources);
    }
    j["statistics"] = {{"minHeight", m.statistics.minHeight},
                       {"maxHeight", m.statistics.maxHeight},
                       {"validSamples", m.statistics.validSamples},
                       {"rootError", m.statistics.rootError}};
    Json levels = Json::array();
    for (const ManifestLevel& l : m.levels) {
        Json level = {{"level", l.level},           {"patchesX", l.patchesX},
                      {"patchesY", l.patchesY},     {"presentPatches", l.presentPatches},
                      {"shardsX", l.shardsX},       {"shardsY", l.shardsY},
                      {"sampleStep", l.sampleStep}, {"maxError", l.maxError}};
        if (m.globe) {
            Json shards = Json::array();
            for (const ShardId& s : l.presentShards) shards.push_back({s.x, s.y});
            level["presentShards"] = std::move(shards);
        }
        levels.push_back(std::move(level));
    }
    j["levels"] = std::move(levels);
    j["source"] = {{"inputs", m.source.inputs},
                   {"reader", m.source.reader},
                   {"sampleType", m.source.sampleType},
                   {"band", m.source.band},
                   {"bandCount", m.source.bandCount},
                   {"rowsFlipped", m.source.rowsFlipped},
                   {"columnsFlipped", m.source.columnsFlipped}};
    if (const auto& r = m.source.resampled)
        j["source"]["resampled"] = {{"method", r->method},
                                    {"width", r->width},
                                    {"height", r->height},
                                    {"geoTransform", r->geoTransform},
                                    {"validSamples", r->validSamples},
                                    {"finestDistanceM", r->finestDistanceM}};
    if (const auto& q = m.quantization)
        j["quantization"] = {{"rule", ManifestQuantization::kRule},
                             {"maxErrorM", q->maxErrorM},
                             {"finestLargestErrorM", q->finestLargestErrorM}};
    if (!m.imagery.empty()) {
        Json layers = Json::array();
        for (const ManifestImageryLayer& l : m.imagery)
            layers.push_back({{"name", l.name},
                              {"kind", l.kind},
                              {"folder", l.folder},
                              {"input", l.input},
                              {"codec", l.codec},
                              {"coarsestLevel", l.coarsestLevel},
                              {"finestLevel", l.finestLevel},
                              {"opacity", l.opacity}});
        j["imagery"] = std::move(layers);
    }
    j["build"] = {
        {"tool", m.build.tool}, {"version", m.build.version}, {"seconds", m.build.seconds}};
    if (m.globe) {
        j["globe"] = {
            {"tiling", ManifestGlobe::kTiling},
            {"levelOffset", ManifestGlobe::kLevelOffset},
            {"faceFinestLevel", m.globe->faceFinestLevel},
            {"sourceExtent", {m.globe->west, m.globe->south, m.globe->east, m.globe->north}}};
        if (!m.globe->seams.empty()) {
            Json seams = Json::array();
            for (const ManifestSeam& s : m.globe->seams)
                seams.push_back({{"input", s.input},
                                 {"seamSlope", s.seamSlope},
                                 {"sourceSlopeP99", s.sourceSlopeP99},
                                 {"bandScaleRatio", s.bandScaleRatio},
                                 {"largestStepM", s.largestStepM},
                                 {"bandPixels", s.bandPixels},
                                 {"bandMetres", s.bandMetres},
                                 {"cappedPixels", s.cappedPixels}});
            j["globe"]["seams"] = std::move(seams);
        }
        if (!m.globe->sources.empty()) {
            Json sources = Json::array();
            for (const ManifestGlobeSource& s : m.globe->sources) {
                Json entry = {{"input", s.input}, {"extent", {s.west, s.south, s.east, s.north}}};
                if (!s.native.empty()) entry["native"] = s.native;
                sources.push_back(std::move(entry));
            }
            j["globe"]["sources"] = std::move(sources);
        }
        if (m.globe->seaLevelM != 0.0) j["globe"]["seaLevelM"] = m.globe->seaLevelM;
        if (m.globe->oversampleLevels != 0)
            j["globe"]["oversampleLevels"] = m.globe->oversampleLevels;
    }
    return j.dump(2) + "\n";
}

Result<PyramidManifest> fromJson(std::string_view json, const std::string& sourceName) {
    Json root;
    try {
        root = Json::parse(json.begin(), json.end());
    } catch (const Json::exception& e) {  // parse_error, and out_of_range for 1E7777777777
        return Error{fmt::format("{}: not valid JSON: {}", sourceName, e.what())};
    }
    if (!root.is_object())
        return Error{
            fmt::format("{}: not a pyramid manifest: the JSON is not an object", sourceName)};
    const auto format = root.find("format");
    if (format == root.end() || !format->is_string())
        return Error{
            fmt::format("{}: not a pyramid manifest: no \"format\" string (expected "
                        "\"{}\")",
                        sourceName, PyramidManifest::kFormatName)};
    if (format->get<std::string>() != PyramidManifest::kFormatName)
        return Error{fmt::format("{}: not a pyramid manifest: \"format\" is \"{}\", not \"{}\"",
                                 sourceName, format->get<std::string>(),
                                 PyramidManifest::kFormatName)};
    // The version decides how the rest reads, so it is checked before anything else.
    const auto version = root.find("formatVersion");
    if (version == root.end() || !version->is_number_integer())
        return Error{fmt::format("{}: \"formatVersion\" is missing or not an integer", sourceName)};
    if (version->get<std::int64_t>() != PyramidManifest::kFormatVersion &&
        version->get<std::int64_t>() != PyramidManifest::kGlobeFormatVersion)
        return Error{
            fmt::format("{}: unsupported formatVersion {} (this program reads versions {} "
                        "(planar) and {} (globe); rebuild the pyramid with terrain-build)",
                        sourceName, version->dump(), PyramidManifest::kFormatVersion,
                        PyramidManifest::kGlobeFormatVersion)};
    PyramidManifest manifest;
    LayoutFields f;
    try {
        manifest = parseFields(root, f);
    } catch (const FieldError& e) {
        return Error{fmt::format("{}: field \"{}\" must be {}", sourceName, e.field, e.expected)};
    }
    if (f.apronSamples != 1)
        return Error{fmt::format("{}: apronSamples is {}; format version 2 has an apron of 1",
                                 sourceName, f.apronSamples)};
    Result<PyramidLayout> layout = PyramidLayout::create(
        f.rasterWidth, f.rasterHeight, f.patchSamples, f.blockQuads, f.shardPatches);
    if (!layout)
        return Error{fmt::format("{}: bad layout: {}", sourceName, layout.error().message)};
    manifest.layout = layout.value();
    if (f.finestLevel != manifest.layout.finestLevel())
        return Error{fmt::format("{}: inconsistent layout: finestLevel is {}, but {} has {}",
                                 sourceName, f.finestLevel, layoutText(manifest.layout),
                                 manifest.layout.finestLevel())};
    if (Status checked = checkManifest(manifest, sourceName); !checked) return checked.error();
    return manifest;
}

Status writeManifest(const std::filesystem::path& pyramidDir, const PyramidManifest& manifest) {
    const std::filesystem::path path = pyramidDir / PyramidManifest::kFileName;
    if (Status checked = checkManifest(manifest, path.string()); !checked) return checked;
    const std::string text = toJson(manifest);
    return writeTextAtomically(path, text);
}

namespace {

// The manifest in the local file `path`, named `name` in messages (a URL for a remote one).
Result<PyramidManifest> readManifestFile(const std::filesystem::path& path,
                                         const std::string& name) {
    std::ifstream in(path, std::ios::binary);
    if (!in.is_open()) return Error{fmt::format("{}: cannot open: {}", name, std::strerror(errno))};
    std::ostringstream text;
    text << in.rdbuf();  // an empty file leaves text empty: a JSON parse error below
    if (in.bad()) return Error{fmt::format("{}: cannot read the file", name)};
    return fromJson(text.str(), name);
}

}  // namespace

Result<PyramidManifest> readManifest(const std::filesystem::path& pyramidDir) {
    Result<std::unique_ptr<remote::RemoteFiles>> files = remote::filesFor(pyramidDir.string());
    if (!files) return files.error();
    return readManifest(pyramidDir, files.value().get());
}

Result<PyramidManifest> readManifest(const std::filesystem::path& pyramidDir,
                                     remote::RemoteFiles* files) {
    if (isVirtualPlanetName(pyramidDir)) {
        Result<VirtualPlanetPyramid> planet = VirtualPlanetPyramid::open(pyramidDir);
        if (!planet) return planet.error();
        return planet.value().manifest();
    }
    if (remote::isRemoteLocation(pyramidDir.string())) {
        // A pyramid on a web server: its manifest through the disk cache, checked with the
        // server (issue 49); errors name the URL.
        if (files == nullptr)
            return Error{fmt::format("{}: a pyramid at a URL read without a RemoteFiles",
                                     pyramidDir.string())};
        const std::string url = remote::joinUrl(pyramidDir.string(), PyramidManifest::kFileName);
        Result<std::filesystem::path> local = files->localCopy(url);
        if (!local)
            return Error{fmt::format("{}: not a pyramid, or not reachable: {}", pyramidDir.string(),
                                     local.error().message)};
        return readManifestFile(local.value(), url);
    }
    const std::filesystem::path path = pyramidDir / PyramidManifest::kFileName;
    std::error_code ec;
    if (!std::filesystem::is_directory(pyramidDir, ec))
        return Error{fmt::format("{}: not a pyramid: no such folder", pyramidDir.string())};
    if (!std::filesystem::is_regular_file(path, ec))
        return Error{fmt::format("{}: not a pyramid: no {}", pyramidDir.string(),
                                 PyramidManifest::kFileName)};
    return readManifestFile(path, path.string());
}

}  // namespace terrain::io
