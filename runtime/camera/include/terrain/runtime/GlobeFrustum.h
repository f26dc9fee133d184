// GlobeFrustum: the view frustum against a globe patch's oriented box (globe::PatchBounds.h),
// for the globe LOD's culling and the globe reference renderer's.
#pragma once

#include "terrain/globe/PatchBounds.h"
#include "terrain/runtime/Camera.h"

namespace terrain::runtime {

/// False when `box` lies entirely outside one plane of `frustum` (conservative, as
/// Frustum::intersects: a box near a corner may pass although it is outside).
bool frustumMeetsBox(const Frustum& frustum, const globe::OrientedBox& box);

}  // namespace terrain::runtime
