// RtinMesh: a view-dependent right-triangulated irregular network over the full-resolution
// samples (Evans, Kirkpatrick & Townsend 2001; the refinement of Lindstrom & Pascucci 2002),
// the "fewest triangles a conforming mesh of this grid needs" yardstick (LodMethod::Rtin).
//
// The grid is padded to (2^k + 1)² vertices (heights clamped to the DEM's edge). Every
// triangle of the bintree is split at the midpoint m of its hypotenuse; m carries
//   e(m): the largest vertical distance from the triangle's plane to any DEM sample inside
//         it — exact over the samples, not the interpolation error at m alone — saturated
//         over the DAG (e(m) ≥ e(c) for the split vertices c of its two children), and
//   r(m): a sphere about m holding the triangle (its corners, raised and lowered by its
//         error) and the children's spheres, r(m) ≥ |m − c| + r(c)
// (Lindstrom & Pascucci 2002, their error saturation and nested bounding spheres).
// A triangle is split when e(m) · verticalErrorPxPerM(the cube about m of radius r(m)) > τ:
// the bound on a vertical segment's on-screen length that Yusov's fine stage is held to
// (EdgeTessellation.h), in place of Lindstrom & Pascucci's isotropic γ · e / (|camera − m|
// − r), which understates errors away from the screen's centre (measured: 4 of 6 Puget
// Sound frames over ε = 1 px, up to 1.24 px). A child's cube lies in its parent's and the
// bound grows with the box, so with both saturations the test stays monotone down the DAG:
// a split vertex's parents are split too, and the two triangles sharing a hypotenuse decide
// it alike. The mesh is conforming (no T-junction), and every sample of an unsplit
// triangle lies within e(m) of it, which projects to at most τ pixels.
// CPU only, no GL.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/runtime/Camera.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace terrain::runtime {

struct RtinTriangle {
    std::uint32_t a, b, c;  ///< grid vertices (row · (n + 1) + column); c is the right angle
};

struct RtinSelectStats {
    std::uint64_t triangles = 0;
    std::uint64_t visited = 0;  ///< bintree nodes looked at
    std::uint64_t culled = 0;   ///< subtrees outside the frustum
};

class RtinMesh {
public:
    /// Default: the arrays of a 4097² grid (about 200 MB).
    static constexpr std::size_t kDefaultMaxBytes = std::size_t{256} << 20;

    /// `heights`: width × height samples, row-major, rows running south; `spacingM`: metres
    /// between samples, east and south. An error when the grid's arrays would need more
    /// than `maxBytes`.
    static Result<RtinMesh> build(int width, int height, std::vector<float> heights,
                                  glm::dvec2 spacingM, std::size_t maxBytes = kDefaultMaxBytes);

    /// The error build() would give for a width × height raster and `maxBytes`, before any
    /// sample is read (the heights and the grid's error and radius arrays).
    static Status checkMemory(int width, int height, std::size_t maxBytes);
    /// n: the padded grid's quads a side, the smallest power of two ≥ the raster's.
    static int gridQuadsFor(int width, int height);

    int width() const { return m_width; }
    int height() const { return m_height; }
    int gridQuads() const { return m_n; }  ///< n: the padded grid has (n + 1)² vertices
    std::size_t memoryBytes() const;

    /// Height of DEM sample (column, row), clamped to the DEM.
    float heightAt(int column, int row) const;
    /// Local metres of grid vertex `v`: x east of sample (0, 0), y north, z the height.
    glm::dvec3 positionOf(std::uint32_t v) const;
    glm::ivec2 sampleOf(std::uint32_t v) const {
        return {static_cast<int>(v % static_cast<std::uint32_t>(m_n + 1)),
                static_cast<int>(v / static_cast<std::uint32_t>(m_n + 1))};
    }
    /// e(m) and r(m) of a grid vertex (0 for vertices that split nothing).
    float errorOf(int column, int row) const { return m_errors[index(column, row)]; }
    float radiusOf(int column, int row) const { return m_radii[index(column, row)]; }

    /// The triangles of the mesh seen by `camera` (world coordinates, in which DEM sample
    /// (0, 0) lies at `originWorld`) at threshold `errorPx`; triangles wholly beyond the DEM
    /// or, when `cull`, outside the camera's frustum are left out. `out` is cleared first.
    RtinSelectStats select(const Camera& camera, glm::dvec2 originWorld, double errorPx, bool cull,
                           std::vector<RtinTriangle>& out) const;

private:
    std::size_t index(int column, int row) const {
        return static_cast<std::size_t>(row) * static_cast<std::size_t>(m_n + 1) +
               static_cast<std::size_t>(column);
    }
    void computeErrors();

    int m_width = 0;
    int m_height = 0;
    int m_n = 0;
    glm::dvec2 m_spacing{1.0};
    std::vector<float> m_heights;  // width × height
    std::vector<float> m_errors;   // (n + 1)²
    std::vector<float> m_radii;    // (n + 1)²
};

}  // namespace terrain::runtime
