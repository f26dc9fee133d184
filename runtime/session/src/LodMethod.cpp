// LodMethod: the table of methods and the parsing of their names.
#include "terrain/runtime/LodMethod.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <array>

namespace terrain::runtime {
namespace {

constexpr std::array kMethods{
    LodMethodInfo{LodMethod::Yusov2011, "yusov2011",
                  "Yusov & Shevtsov 2011: patch quadtree + per-edge hardware tessellation from "
                  "block errors",
                  true, true, false, true, true},
    LodMethodInfo{LodMethod::ChunkedLod, "chunked-lod",
                  "Ulrich 2002: chunk quadtree split on projected geometric error, full-resolution "
                  "chunks with skirts",
                  true, true, false, false, true},
    LodMethodInfo{LodMethod::Uniform, "uniform",
                  "the uniform full-resolution grid: every finest patch in view, fully tessellated",
                  true, true, false, false, true},
    LodMethodInfo{LodMethod::Livny2007, "livny2007",
                  "Livny et al. 2007: patch quadtree by edge distance (Eq. 1), four triangular "
                  "tiles a patch at their edges' resolutions",
                  false, false, false, false, true},
    LodMethodInfo{LodMethod::Valdetaro2011, "valdetaro2011",
                  "Valdetaro et al. 2011: flat grid of tiles, per-tile hardware tessellation from "
                  "its height-acceleration map, screen error and distance",
                  false, false, false, false, true},
    LodMethodInfo{LodMethod::Cdlod, "cdlod",
                  "Strugar 2009: patch quadtree by distance ranges, regular grids morphed towards "
                  "the coarser level",
                  false, false, false, false, true},
    LodMethodInfo{LodMethod::Lee2011, "lee2011",
                  "Lee & Shin 2011: the whole finest level's quadtree built on the GPU by vertex "
                  "splitting (roughness, Eq. 2-3), T-junctions removed by triangle splitting",
                  false, false, true, false, false},
    LodMethodInfo{LodMethod::Ripolles, "ripolles",
                  "Ripolles et al.: GPU tessellation of four input triangles by distance with "
                  "Schmiade's seven patterns, one step a frame from the previous tessellation",
                  false, false, true, false, false},
    LodMethodInfo{LodMethod::Rtin, "rtin",
                  "view-dependent RTIN from the full-resolution samples, exact per-vertex errors "
                  "(the fewest-triangles yardstick)",
                  true, false, true, false, false},
};

std::string_view trimmed(std::string_view s) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    return s;
}

}  // namespace

std::span<const LodMethodInfo> lodMethods() { return kMethods; }

Status lodMethodSupports(LodMethod method, SurfaceKind surface) {
    if (surface == SurfaceKind::Plane || lodMethodInfo(method).globe) return {};
    std::string drawing;
    for (const LodMethodInfo& info : kMethods)
        if (info.globe)
            drawing += std::string(drawing.empty() ? "" : ", ") + std::string(info.name);
    return Error{std::string(lodMethodName(method)) +
                 " draws planar pyramids only; on a globe: " + drawing};
}

const LodMethodInfo& lodMethodInfo(LodMethod method) {
    for (const LodMethodInfo& info : kMethods) {
        if (info.method == method) return info;
    }
    TERRAIN_ASSERT(false, "LodMethod: a method missing from the table");
    return kMethods.front();
}

std::string lodMethodNames() {
    std::string names;
    for (const LodMethodInfo& info : kMethods) {
        if (!names.empty()) names += ", ";
        names += info.name;
    }
    return names;
}

Result<LodMethod> parseLodMethod(std::string_view name) {
    const std::string_view wanted = trimmed(name);
    for (const LodMethodInfo& info : kMethods) {
        if (info.name == wanted) return info.method;
    }
    return Error{"unknown LOD method '" + std::string(wanted) + "' (methods: " + lodMethodNames() +
                 ")"};
}

Result<std::vector<LodMethod>> parseLodMethods(std::string_view list) {
    std::vector<LodMethod> methods;
    if (trimmed(list) == "all") {
        for (const LodMethodInfo& info : kMethods) methods.push_back(info.method);
        return methods;
    }
    while (true) {
        const std::size_t comma = list.find(',');
        auto method = parseLodMethod(list.substr(0, comma));
        if (!method) return method.error();
        if (std::find(methods.begin(), methods.end(), method.value()) != methods.end())
            return Error{"LOD method '" + std::string(lodMethodName(method.value())) +
                         "' given twice"};
        methods.push_back(method.value());
        if (comma == std::string_view::npos) break;
        list.remove_prefix(comma + 1);
    }
    return methods;
}

}  // namespace terrain::runtime
