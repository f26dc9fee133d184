// RtinMesh: the bintree's exact errors and nested spheres, level by level from the finest,
// and the per-frame refinement.
#include "terrain/runtime/RtinMesh.h"

#include "terrain/base/Assert.h"
#include "terrain/runtime/EdgeTessellation.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace terrain::runtime {
namespace {

struct Tri {
    int ax, ay, bx, by, cx, cy;  // a–b the hypotenuse, c the right angle
};

bool splittable(const Tri& t) { return std::abs(t.ax - t.cx) + std::abs(t.ay - t.cy) > 1; }

// The two children of a split triangle (Evans et al. 2001): the hypotenuse's midpoint m
// becomes the right angle of both.
void childrenOf(const Tri& t, Tri& left, Tri& right) {
    const int mx = (t.ax + t.bx) / 2;
    const int my = (t.ay + t.by) / 2;
    left = {t.cx, t.cy, t.ax, t.ay, mx, my};
    right = {t.bx, t.by, t.cx, t.cy, mx, my};
}

// Visits every triangle `depth` levels below `t`.
template <typename F>
void forEachAtDepth(const Tri& t, int depth, F&& visit) {
    if (depth == 0) {
        visit(t);
        return;
    }
    if (!splittable(t)) return;
    Tri left, right;
    childrenOf(t, left, right);
    forEachAtDepth(left, depth - 1, visit);
    forEachAtDepth(right, depth - 1, visit);
}

std::int64_t edgeFunction(int ax, int ay, int bx, int by, int px, int py) {
    return static_cast<std::int64_t>(bx - ax) * (py - ay) -
           static_cast<std::int64_t>(by - ay) * (px - ax);
}

}  // namespace

int RtinMesh::gridQuadsFor(int width, int height) {
    int n = 1;
    while (n < std::max(width, height) - 1) n *= 2;
    return n;
}

Status RtinMesh::checkMemory(int width, int height, std::size_t maxBytes) {
    const int n = gridQuadsFor(width, height);
    const std::size_t vertices = static_cast<std::size_t>(n + 1) * static_cast<std::size_t>(n + 1);
    const std::size_t samples = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const std::size_t bytes = (vertices * 2 + samples) * sizeof(float);
    if (bytes <= maxBytes) return {};
    return Error{fmt::format(
        "the RTIN yardstick holds the whole finest level in memory: this raster of {} × {} "
        "samples needs {:.0f} MiB (limit {:.0f} MiB)",
        width, height, static_cast<double>(bytes) / (1 << 20),
        static_cast<double>(maxBytes) / (1 << 20))};
}

Result<RtinMesh> RtinMesh::build(int width, int height, std::vector<float> heights,
                                 glm::dvec2 spacingM, std::size_t maxBytes) {
    TERRAIN_ASSERT(
        width >= 2 && height >= 2 &&
            heights.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height),
        "RtinMesh: bad raster");
    if (auto fits = checkMemory(width, height, maxBytes); !fits) return fits.error();
    const int n = gridQuadsFor(width, height);
    const std::size_t vertices = static_cast<std::size_t>(n + 1) * static_cast<std::size_t>(n + 1);
    RtinMesh mesh;
    mesh.m_width = width;
    mesh.m_height = height;
    mesh.m_n = n;
    mesh.m_spacing = spacingM;
    mesh.m_heights = std::move(heights);
    mesh.m_errors.assign(vertices, 0.0f);
    mesh.m_radii.assign(vertices, 0.0f);
    mesh.computeErrors();
    return mesh;
}

std::size_t RtinMesh::memoryBytes() const {
    return (m_heights.size() + m_errors.size() + m_radii.size()) * sizeof(float);
}

float RtinMesh::heightAt(int column, int row) const {
    column = std::clamp(column, 0, m_width - 1);
    row = std::clamp(row, 0, m_height - 1);
    return m_heights[static_cast<std::size_t>(row) * static_cast<std::size_t>(m_width) +
                     static_cast<std::size_t>(column)];
}

glm::dvec3 RtinMesh::positionOf(std::uint32_t v) const {
    const glm::ivec2 s = sampleOf(v);
    return {s.x * m_spacing.x, -s.y * m_spacing.y, static_cast<double>(heightAt(s.x, s.y))};
}

void RtinMesh::computeErrors() {
    const auto local = [&](int x, int y) {
        return glm::dvec3(x * m_spacing.x, -y * m_spacing.y, static_cast<double>(heightAt(x, y)));
    };
    // The largest vertical distance between the triangle's plane and the DEM samples in it
    // (edges included; samples beyond the DEM are not data and do not count).
    const auto exactError = [&](const Tri& t) {
        const int x0 = std::min({t.ax, t.bx, t.cx});
        const int y0 = std::min({t.ay, t.by, t.cy});
        const int x1 = std::min(std::max({t.ax, t.bx, t.cx}), m_width - 1);
        const int y1 = std::min(std::max({t.ay, t.by, t.cy}), m_height - 1);
        if (x0 > x1 || y0 > y1) return 0.0;
        const std::int64_t area = edgeFunction(t.ax, t.ay, t.bx, t.by, t.cx, t.cy);
        const double ha = heightAt(t.ax, t.ay), hb = heightAt(t.bx, t.by),
                     hc = heightAt(t.cx, t.cy);
        double worst = 0.0;
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                // Barycentric weights by edge functions, signed like the whole triangle.
                const std::int64_t wa = edgeFunction(t.bx, t.by, t.cx, t.cy, x, y);
                const std::int64_t wb = edgeFunction(t.cx, t.cy, t.ax, t.ay, x, y);
                const std::int64_t wc = edgeFunction(t.ax, t.ay, t.bx, t.by, x, y);
                const bool inside =
                    area > 0 ? (wa >= 0 && wb >= 0 && wc >= 0) : (wa <= 0 && wb <= 0 && wc <= 0);
                if (!inside) continue;
                const double plane = (static_cast<double>(wa) * ha + static_cast<double>(wb) * hb +
                                      static_cast<double>(wc) * hc) /
                                     static_cast<double>(area);
                worst = std::max(worst, std::abs(static_cast<double>(heightAt(x, y)) - plane));
            }
        }
        return worst;
    };

    const Tri roots[2] = {{0, 0, m_n, m_n, m_n, 0}, {m_n, m_n, 0, 0, 0, m_n}};
    int levels = 0;  // splittable depths are 0 .. levels − 1
    for (int side = m_n; side > 1; side /= 2) levels += 2;
    if (m_n == 1) levels = 0;
    // Finest first: a vertex's error and sphere are final (both triangles that split at it
    // have given theirs) before the coarser triangles that contain it read them.
    for (int depth = levels - 1; depth >= 0; --depth) {
        for (const Tri& root : roots) {
            forEachAtDepth(root, depth, [&](const Tri& t) {
                if (!splittable(t)) return;
                const int mx = (t.ax + t.bx) / 2;
                const int my = (t.ay + t.by) / 2;
                const std::size_t m = index(mx, my);
                const double own = exactError(t);
                double error = own;
                const glm::dvec3 pm = local(mx, my);
                double radius = 0.0;
                for (const glm::ivec2 corner :
                     {glm::ivec2(t.ax, t.ay), glm::ivec2(t.bx, t.by), glm::ivec2(t.cx, t.cy)}) {
                    radius = std::max(radius, glm::distance(pm, local(corner.x, corner.y)) + own);
                }
                Tri left, right;
                childrenOf(t, left, right);
                for (const Tri& child : {left, right}) {
                    if (!splittable(child)) continue;
                    const int cx = (child.ax + child.bx) / 2;
                    const int cy = (child.ay + child.by) / 2;
                    const std::size_t c = index(cx, cy);
                    error = std::max(error, static_cast<double>(m_errors[c]));
                    radius = std::max(
                        radius, glm::distance(pm, local(cx, cy)) + static_cast<double>(m_radii[c]));
                }
                // Rounded up to float, so the stored values still bound what they bound.
                const auto up = [](double v) {
                    const auto f = static_cast<float>(v);
                    return static_cast<double>(f) < v
                               ? std::nextafter(f, std::numeric_limits<float>::infinity())
                               : f;
                };
                m_errors[m] = std::max(m_errors[m], up(error));
                m_radii[m] = std::max(m_radii[m], up(radius));
            });
        }
    }
}

RtinSelectStats RtinMesh::select(const Camera& camera, glm::dvec2 originWorld, double errorPx,
                                 bool cull, std::vector<RtinTriangle>& out) const {
    out.clear();
    RtinSelectStats stats;
    const glm::dvec3 cameraLocal = camera.position - glm::dvec3(originWorld, 0.0);
    const Frustum frustumOfCamera = camera.frustum();
    const Frustum* frustum = cull ? &frustumOfCamera : nullptr;
    const glm::dmat4 viewProjection = camera.relativeViewProjection();
    const glm::dvec2 viewportPx(camera.viewportWidth, camera.viewportHeight);
    const auto local = [&](int x, int y) {
        return glm::dvec3(x * m_spacing.x, -y * m_spacing.y, static_cast<double>(heightAt(x, y)));
    };
    const auto vertex = [&](int x, int y) { return static_cast<std::uint32_t>(index(x, y)); };
    const auto visible = [&](const glm::dvec3& lo, const glm::dvec3& hi) {
        if (frustum == nullptr) return true;
        const glm::dvec3 origin(originWorld, 0.0);
        return frustum->intersects(Aabb{.min = lo + origin, .max = hi + origin});
    };
    const auto visit = [&](const auto& self, const Tri& t) -> void {
        ++stats.visited;
        if (std::min({t.ax, t.bx, t.cx}) > m_width - 1 ||
            std::min({t.ay, t.by, t.cy}) > m_height - 1)
            return;  // wholly in the padding beyond the DEM
        if (splittable(t)) {
            const int mx = (t.ax + t.bx) / 2;
            const int my = (t.ay + t.by) / 2;
            const glm::dvec3 pm = local(mx, my);
            const double r = m_radii[index(mx, my)];
            if (!visible(pm - glm::dvec3(r), pm + glm::dvec3(r))) {
                ++stats.culled;
                return;
            }
            const double e = m_errors[index(mx, my)];
            if (e > 0.0) {
                const glm::dvec3 fromCamera = pm - cameraLocal;
                const Aabb cube{.min = fromCamera - glm::dvec3(r),
                                .max = fromCamera + glm::dvec3(r)};
                if (e * verticalErrorPxPerM(viewProjection, viewportPx, cube) > errorPx) {
                    Tri left, right;
                    childrenOf(t, left, right);
                    self(self, left);
                    self(self, right);
                    return;
                }
            }
        } else {
            const glm::dvec3 pa = local(t.ax, t.ay), pb = local(t.bx, t.by), pc = local(t.cx, t.cy);
            if (!visible(glm::min(pa, glm::min(pb, pc)), glm::max(pa, glm::max(pb, pc)))) {
                ++stats.culled;
                return;
            }
        }
        out.push_back({vertex(t.ax, t.ay), vertex(t.bx, t.by), vertex(t.cx, t.cy)});
    };
    visit(visit, Tri{0, 0, m_n, m_n, m_n, 0});
    visit(visit, Tri{m_n, m_n, 0, 0, 0, m_n});
    stats.triangles = out.size();
    return stats;
}

}  // namespace terrain::runtime
