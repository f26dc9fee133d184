// PatchSelection: a depth-first walk from the root; see the header for the rule.
#include "terrain/runtime/PatchSelection.h"

#include <algorithm>
#include <limits>

namespace terrain::runtime {

namespace {

class Selector {
public:
    Selector(const Camera& camera, const TerrainGeometry& geometry, double errorPx,
             TileResidency& residency, std::vector<PatchDraw>& out)
        : m_camera(camera),
          m_frustum(camera.frustum()),
          m_gamma(camera.errorScale()),
          m_geometry(geometry),
          m_errorPx(errorPx),
          m_residency(residency),
          m_out(out) {}

    void visit(const io::PatchId& id, const io::PatchInfo& info) {
        ++m_stats.visited;
        const Aabb box = m_geometry.patchBounds(id, info);
        if (!m_frustum.intersects(box)) {
            ++m_stats.culled;
            m_stats.coveredFinestPatches += finestPatchesCovered(m_geometry.layout(), id);
            return;
        }
        const double screenError = this->screenError(info, box);
        if (screenError > m_errorPx && id.level < m_geometry.layout().finestLevel()) {
            io::PatchId children[4];
            const io::PatchInfo* childInfo[4] = {};
            const int count = containedChildren(m_geometry.layout(), id, children);
            bool allResident = true;
            // Every missing child is asked for with the parent's screen-space error, so the
            // I/O thread serves the coarsest-looking parts of the view first.
            const auto priority = static_cast<float>(
                std::min(screenError, static_cast<double>(std::numeric_limits<float>::max())));
            for (int i = 0; i < count; ++i) {
                childInfo[i] = m_residency.acquire(children[i], priority);
                allResident = allResident && childInfo[i] != nullptr;
            }
            if (allResident) {
                for (int i = 0; i < count; ++i) visit(children[i], *childInfo[i]);
                return;
            }
            ++m_stats.waitingSplits;
        }
        m_out.push_back(PatchDraw::ofTile(id, m_residency.layerOf(id), info));
        ++m_stats.drawn;
        m_stats.coveredFinestPatches += finestPatchesCovered(m_geometry.layout(), id);
    }

    const PatchSelectionStats& stats() const { return m_stats; }

private:
    // Err_Scr(P) = γ · Err(P) / ρ(c, V) (Yusov & Shevtsov 2011, §5); infinite inside V
    // unless the patch is exact.
    double screenError(const io::PatchInfo& info, const Aabb& box) const {
        if (info.error <= 0.0f) return 0.0;
        const double rho = distanceToBox(m_camera.position, box);
        if (rho <= 0.0) return std::numeric_limits<double>::infinity();
        return m_gamma * static_cast<double>(info.error) / rho;
    }

    const Camera& m_camera;
    const Frustum m_frustum;
    const double m_gamma;
    const TerrainGeometry& m_geometry;
    const double m_errorPx;
    TileResidency& m_residency;
    std::vector<PatchDraw>& m_out;
    PatchSelectionStats m_stats;
};

}  // namespace

PatchSelectionStats selectPatches(const Camera& camera, const TerrainGeometry& geometry,
                                  double errorPx, TileResidency& residency,
                                  std::vector<PatchDraw>& out) {
    out.clear();
    const io::PatchId root{0, 0, 0};
    const io::PatchInfo* rootInfo = residency.acquire(root, std::numeric_limits<float>::max());
    if (rootInfo == nullptr) return {};
    Selector selector(camera, geometry, errorPx, residency, out);
    selector.visit(root, *rootInfo);
    return selector.stats();
}

}  // namespace terrain::runtime
