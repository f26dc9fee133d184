// TestCameras: the camera poses the streaming and LOD tests fly, given as fractions of the
// DEM's extent, so each test says where it looks rather than how a camera is built.
#pragma once

#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

namespace terrain::test {

/// A 640 × 480 camera (1 rad vertical field of view) `aboveM` metres over the DEM's highest
/// point at fractions (fx, fy) of its extent, looking at fractions (tx, ty) on the plane of
/// its lowest point (0, 0 is the north-west corner).
inline runtime::Camera cameraOverDem(const runtime::TerrainGeometry& g, double fx, double fy,
                                     double aboveM, double tx, double ty) {
    runtime::Camera c;
    c.viewportWidth = 640;
    c.viewportHeight = 480;
    c.fovY = 1.0;
    c.position = {g.worldAtFraction(fx, fy), g.maxHeight() + aboveM};
    c.lookAt({g.worldAtFraction(tx, ty), g.minHeight()});
    return c;
}

}  // namespace terrain::test
