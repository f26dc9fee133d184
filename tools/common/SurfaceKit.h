// SurfaceKit: what a program that flies a pyramid does differently on the plane and on the
// globe, in one place, so the program itself is one code path (PlaneKit, GlobeKit): the camera
// path's format and the default flight (the globe's fixed pose too), when each frame is taken
// from the path, the sky and the fog, what a failed root means, which LOD methods and flags the
// surface refuses, and the report's fields of one surface only (PlaneKit.cpp, GlobeKit.cpp).
// No GL.
#pragma once

#include "DrawStyleFlags.h"
#include "GlobeFlags.h"

#include "terrain/base/Result.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/FlightPath.h"
#include "terrain/runtime/LodMethod.h"
#include "terrain/runtime/PatchDraw.h"
#include "terrain/runtime/Surface.h"
#include "terrain/runtime/TerrainStyle.h"
#include "terrain/runtime/TileStreamer.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace terrain::tools {

/// What a flight left for the report's surface-only fields (SurfaceKit::addJsonFields).
struct FlightFacts {
    std::string pathFile;        ///< --path; empty: the kit's default flight
    bool fixedPose = false;      ///< the globe's fixed pose was flown (GlobeFlags)
    double fps = 0.0;            ///< --fps
    runtime::Camera lastCamera;  ///< the camera of the last frame
    std::span<const runtime::PatchDraw> lastDraws;  ///< the last frame's draw list
    bool horizonCulling = true;
    std::uint64_t horizonCulled = 0;  ///< patches culled behind the horizon, all frames
    std::uint64_t visited = 0;        ///< patches the LOD visited, all frames
    nlohmann::json arrival;           ///< full detail after arrival (measuresArrival), or null
};

/// A flight and what the program says of it (SurfaceKit::flight).
struct Flight {
    runtime::FlightPath path;
    /// On the globe, where the flight goes and how to pick another place (GlobeKit's
    /// describeFlightPlan): one line for stderr; empty where there is nothing to say (a path
    /// file, the plane).
    std::string said;
    /// The report's fields of the globe's default flight (flightPlanJson): the places it
    /// visits; null otherwise.
    nlohmann::json report;
};

class SurfaceKit {
public:
    virtual ~SurfaceKit() = default;

    /// The kit of `kind`'s surface; of the surface `manifest` describes.
    static std::unique_ptr<SurfaceKit> of(runtime::SurfaceKind kind);
    static std::unique_ptr<SurfaceKit> of(const io::PyramidManifest& manifest);

    virtual runtime::SurfaceKind kind() const = 0;
    /// "planar" or "globe", as reports say.
    std::string_view tiling() const { return runtime::surfaceName(kind()); }
    /// The camera path format this surface flies.
    virtual runtime::PathFrame pathFrame() const = 0;

    /// Ok when `method` draws this surface; else "<pyramid>: a globe pyramid: <why>", the
    /// words TerrainSession::open refuses it with (lodMethodSupports).
    Status supports(const std::string& pyramid, runtime::LodMethod method) const;
    /// Ok unless the command line gave flags of the other surface: "<pyramid>: a planar
    /// pyramid; --lat, --pitch are for globe pyramids only".
    Status refuseForeignFlags(const std::string& pyramid, const GlobeFlags& globe) const;

    /// The flight: on the globe a fixed pose where `globe` gives one; else `pathFile` read as
    /// this surface's path (the other surface's format refused by name); else the surface's
    /// default flight, `durationS` long, over `surface` (the pyramid's): on the globe every
    /// place of the data in turn, or the one --visit picks (GlobeKit.h).
    virtual Result<Flight> flight(const std::string& pyramid, const runtime::Surface& surface,
                                  const std::string& pathFile, double durationS,
                                  const GlobeFlags& globe) const = 0;

    /// The path time of frame `frame` of `frames`: every 1 / fps from the start on the plane,
    /// spread evenly over the whole path on the globe (start to end whatever the fps).
    virtual double frameTimeS(const runtime::FlightPath& path, std::uint64_t frame,
                              std::uint64_t frames, double fps) const = 0;

    /// The look: debug view, wireframe and skirts from `look`, then skyAndFog.
    void applyLook(runtime::TerrainStyle& style, const DrawStyleFlags& look,
                   const runtime::Surface& surface) const;
    /// The sky (space on the globe) and the fog (from the DEM's extent or --fog on the plane,
    /// none on the globe).
    virtual void skyAndFog(runtime::TerrainStyle& style, const DrawStyleFlags& look,
                           const runtime::Surface& surface) const = 0;

    /// The camera's height above the surface's datum: the DEM's zero on the plane, the
    /// ellipsoid on the globe.
    virtual double cameraHeightM(const runtime::Camera& camera) const = 0;

    /// What an accuracy probe clears both images to (AccuracyProbeOptions::clearColor): a
    /// colour the terrain's shading never produces, so a pixel of it in the LOD where the
    /// reference drew ground is uncovered. Magenta on the plane; space on the globe, whose
    /// frames are mostly space, as a user sees them (PSNR counts it).
    virtual std::array<float, 4> measureBackground() const = 0;

    /// Why a failed root ends the run, before the fault's message.
    virtual std::string_view rootFaultMessage() const = 0;

    /// Adds the report's fields of this surface only ("fps" on the plane; the end pose, the
    /// last frame's patches by level, horizon culling and arrival on the globe) and "path".
    virtual void addJsonFields(nlohmann::json& out, const FlightFacts& facts) const = 0;
};

/// The two kits (PlaneKit.cpp, GlobeKit.cpp); SurfaceKit::of picks one.
std::unique_ptr<SurfaceKit> makePlaneKit();
std::unique_ptr<SurfaceKit> makeGlobeKit();

}  // namespace terrain::tools
