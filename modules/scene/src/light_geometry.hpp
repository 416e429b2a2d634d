// Geometry shared by the built-in lights (private): points on triangles, the rectangle two
// triangles tile, when a rectangle is sampled by solid angle.
#pragma once

#include <vector>

#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/spherical_rectangle.hpp"

namespace ps {

/// A point on a triangle from two uniform numbers (uniform in area).
inline Vec3f pointOnTriangle(const EmitterTriangle& tri, float a, float b) {
  const float su = std::sqrt(a);
  return Vec3f(tri.p0 + tri.e1 * (su * (1 - b)) + tri.e2 * (su * b));
}

/// Mesh triangle `t` as an EmitterTriangle (n its unit face normal by winding); false for a
/// degenerate triangle (zero area or normal), which no light samples.
bool meshTriangle(const Mesh& mesh, int t, EmitterTriangle* tri);

/// The rectangle that `tris` tile exactly (two triangles on either side of one of its
/// diagonals, perpendicular edges, the same facing), or an invalid one.
EmitterRectangle rectangleOf(const std::vector<const EmitterTriangle*>& tris);

/// Solid-angle sampling of a rectangle is used from x when its solid angle is in this range
/// (below it, area sampling is as good and better conditioned).
constexpr float kMinSphericalSolidAngle = 1e-4f, kMaxSphericalSolidAngle = 6.2f;
inline bool useSpherical(const SphericalRectangle& sr) {
  return sr.valid() && sr.solidAngle() > kMinSphericalSolidAngle &&
         sr.solidAngle() < kMaxSphericalSolidAngle;
}

/// The part id of `name`, or ps::InputError(file, key, "unknown part ...").
int requirePartId(const std::vector<Part>& parts, const std::string& name, const std::string& file,
                  const std::string& key);

}  // namespace ps
