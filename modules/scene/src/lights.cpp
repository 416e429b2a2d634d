// The automatic ceiling grid (the lights themselves: area_light.cpp, environment_light.cpp).
#include "photoscene/scene/lights.hpp"

#include <cmath>

#include "photoscene/core/error.hpp"
#include "photoscene/scene/mesh.hpp"

namespace ps {

std::vector<AreaLight> autoCeilingLights(const Mesh& mesh, const Vec3f& upIn, float spacing,
                                         float size, float offset) {
  PS_CheckGT(spacing, 0.0f, "auto ceiling spacing");
  const Vec3f up = upIn.normalized();
  Vec3f e1, e2;
  horizontalAxes(up, &e1, &e2);
  float lo1 = INFINITY, hi1 = -INFINITY, lo2 = INFINITY, hi2 = -INFINITY, top = -INFINITY;
  for (const auto& f : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Vec3f& p = mesh.positions[f[k]];
      lo1 = std::min(lo1, p.dot(e1));
      hi1 = std::max(hi1, p.dot(e1));
      lo2 = std::min(lo2, p.dot(e2));
      hi2 = std::max(hi2, p.dot(e2));
      top = std::max(top, p.dot(up));
    }
  }
  std::vector<AreaLight> lights;
  if (!std::isfinite(top)) return lights;
  const float ext1 = hi1 - lo1, ext2 = hi2 - lo2;
  const int n1 = std::max(1, static_cast<int>(std::ceil(ext1 / spacing - 1e-4f)));
  const int n2 = std::max(1, static_cast<int>(std::ceil(ext2 / spacing - 1e-4f)));
  const float side1 = std::min(size, 0.5f * ext1 / n1), side2 = std::min(size, 0.5f * ext2 / n2);
  for (int i = 0; i < n1; ++i) {
    for (int j = 0; j < n2; ++j) {
      AreaLight l;
      l.name = "ceiling_" + std::to_string(i * n2 + j);
      l.kind = AreaLight::Kind::Rectangle;
      l.automatic = true;
      const float a = lo1 + (i + 0.5f) * ext1 / n1, b = lo2 + (j + 0.5f) * ext2 / n2;
      l.center = a * e1 + b * e2 + (top - offset) * up;
      l.edgeU = side1 * e1;
      l.edgeV = -side2 * e2;  // e1 x (-e2) = -up: emits downward
      lights.push_back(l);
    }
  }
  return lights;
}

}  // namespace ps
