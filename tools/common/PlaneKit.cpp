// PlaneKit: the plane's side of SurfaceKit: the planar flight, frame times, look and report
// fields.
#include "SurfaceKit.h"

#include "terrain/runtime/CameraPath.h"
#include "terrain/runtime/PlaneSurface.h"

namespace terrain::tools {
namespace {

// The plane: a planar camera path in the pyramid's metres and CameraPath::defaultFor, a frame
// every 1 / fps, the daylight sky with fog from the DEM's extent.
class PlaneKit final : public SurfaceKit {
public:
    runtime::SurfaceKind kind() const override { return runtime::SurfaceKind::Plane; }
    runtime::PathFrame pathFrame() const override { return runtime::PathFrame::Plane; }

    Result<Flight> flight(const std::string& /*pyramid*/, const runtime::Surface& surface,
                          const std::string& pathFile, double durationS,
                          const GlobeFlags& /*globe: refused*/) const override {
        if (!pathFile.empty()) {
            auto loaded = runtime::FlightPath::load(pathFile, pathFrame());
            if (!loaded) return loaded.error();
            return Flight{std::move(loaded).value(), {}, nullptr};
        }
        return Flight{runtime::FlightPath(runtime::CameraPath::defaultFor(
                          runtime::planeGeometry(surface), durationS)),
                      {},
                      nullptr};
    }

    double frameTimeS(const runtime::FlightPath& path, std::uint64_t frame,
                      std::uint64_t /*frames*/, double fps) const override {
        return path.startS() + static_cast<double>(frame) / fps;
    }

    void skyAndFog(runtime::TerrainStyle& style, const DrawStyleFlags& look,
                   const runtime::Surface& surface) const override {
        // The default sky (TerrainStyle's daylight).
        style.fogDensityPerM = look.fogDensityPerM(runtime::planeGeometry(surface));
    }

    double cameraHeightM(const runtime::Camera& camera) const override { return camera.position.z; }

    std::array<float, 4> measureBackground() const override { return {1.0f, 0.0f, 1.0f, 1.0f}; }

    std::string_view rootFaultMessage() const override {
        return "nothing to draw, the root patch failed: ";
    }

    void addJsonFields(nlohmann::json& out, const FlightFacts& facts) const override {
        out["path"] =
            facts.pathFile.empty() ? nlohmann::json("default") : nlohmann::json(facts.pathFile);
        out["fps"] = facts.fps;
        out["full_detail_after_arrival"] = facts.arrival;
    }
};

}  // namespace

std::unique_ptr<SurfaceKit> makePlaneKit() { return std::make_unique<PlaneKit>(); }

}  // namespace terrain::tools
