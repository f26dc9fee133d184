// GlobeGroundHeight: down the face quadtree through present children, then the heights of the
// last patch's cell under the point.
#include "terrain/pyramid/GlobeGroundHeight.h"

#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace terrain::io {

Result<GlobeGroundQuery> GlobeGroundQuery::open(const std::filesystem::path& pyramid) {
    auto reader = PyramidReader::open(pyramid);
    if (!reader) return reader.error();
    if (!reader.value().manifest().globe)
        return Error{pyramid.string() +
                     ": not a globe pyramid; the ground of a planar pyramid is in its world "
                     "coordinates"};
    return GlobeGroundQuery(std::move(reader).value());
}

Result<GlobeGround> GlobeGroundQuery::at(double latitudeDeg, double longitudeDeg) {
    auto cell = cellHeights(latitudeDeg, longitudeDeg);
    if (!cell) return cell.error();
    return GlobeGround{std::max(cell.value().alongAD, cell.value().alongBC),
                       cell.value().faceLevel};
}

Result<std::pair<double, double>> GlobeGroundQuery::heightsAt(double latitudeDeg,
                                                              double longitudeDeg) {
    auto cell = cellHeights(latitudeDeg, longitudeDeg);
    if (!cell) return cell.error();
    return std::pair{cell.value().alongAD, cell.value().alongBC};
}

Result<const PatchRecord*> GlobeGroundQuery::patch(const PatchId& id) {
    if (auto kept = m_patches.find(id); kept != m_patches.end()) return &kept->second;
    if (m_patches.size() >= kCachedPatches) m_patches.clear();
    PatchRecord record;
    if (Status read = m_reader.readPatch(id, record); !read) return read.error();
    return &m_patches.emplace(id, std::move(record)).first->second;
}

Result<PatchInfo> GlobeGroundQuery::info(const PatchId& id) {
    if (auto kept = m_infos.find(id); kept != m_infos.end()) return kept->second;
    if (m_infos.size() >= kCachedInfos) m_infos.clear();
    auto read = m_reader.patchInfo(id);
    if (!read) return read.error();
    return m_infos.emplace(id, read.value()).first->second;
}

Result<GlobeGroundQuery::CellHeights> GlobeGroundQuery::cellHeights(double latitudeDeg,
                                                                    double longitudeDeg) {
    PyramidReader& reader = m_reader;
    const PyramidManifest& manifest = reader.manifest();
    const glm::dvec3 normal = globe::Wgs84::normalAt(latitudeDeg, longitudeDeg);
    const globe::FacePoint point = globe::facePointOf(normal);
    globe::GlobePatchId id{point.face, 0, 0, 0};
    auto info = this->info(layoutPatchOf(id));
    if (!info) return info.error();
    if (!info.value().present) return CellHeights{};
    for (;;) {
        const int level = id.level + 1;
        const std::int64_t side = globe::patchesPerFaceSide(level);
        const auto cell = [&](double f) {
            return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(f * double(side))),
                                            0, side - 1);
        };
        const globe::GlobePatchId child{point.face, level, cell(point.s), cell(point.t)};
        const int quadrant = static_cast<int>((child.x & 1) + 2 * (child.y & 1));
        if (((info.value().presentChildren >> quadrant) & 1) == 0) break;
        auto childInfo = this->info(layoutPatchOf(child));
        if (!childInfo) return childInfo.error();
        if (!childInfo.value().present) break;
        id = child;
        info = std::move(childInfo);
    }
    auto record = patch(layoutPatchOf(id));
    if (!record) return record.error();
    // The point's cell in the patch and where in it; heights interpolated on the cell's two
    // triangulations in sample space, as virtual children and the tessellator sample them
    // (along the normal, so a coarse patch's flat triangles do not sag under the point).
    const int quads = manifest.layout.patchQuads();
    const int tile = quads + 3;  // the one-sample apron on each side
    const double n = static_cast<double>(globe::patchesPerFaceSide(id.level));
    const double gx = std::clamp((point.s * n - double(id.x)) * quads, 0.0, double(quads));
    const double gy = std::clamp((point.t * n - double(id.y)) * quads, 0.0, double(quads));
    const int ci = std::min(static_cast<int>(gx), quads - 1);
    const int cj = std::min(static_cast<int>(gy), quads - 1);
    const double u = gx - ci, v = gy - cj;
    const auto index = [&](int i, int j) {
        return static_cast<std::size_t>((j + 1) * tile + i + 1);
    };
    const std::vector<float>& h = record.value()->heights;
    const double a = h[index(ci, cj)], b = h[index(ci + 1, cj)];
    const double c = h[index(ci, cj + 1)], d = h[index(ci + 1, cj + 1)];
    const double alongAD = u >= v ? a + u * (b - a) + v * (d - b) : a + v * (c - a) + u * (d - c);
    const double alongBC = u + v <= 1.0 ? a + u * (b - a) + v * (c - a)
                                        : d + (1.0 - u) * (c - d) + (1.0 - v) * (b - d);
    const std::vector<std::uint8_t>& valid = record.value()->valid;
    const bool data = valid.empty() || valid[index(ci, cj)] || valid[index(ci + 1, cj)] ||
                      valid[index(ci, cj + 1)] || valid[index(ci + 1, cj + 1)];
    return CellHeights{alongAD, alongBC, data ? id.level : -1};
}

}  // namespace terrain::io
