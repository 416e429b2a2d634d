// Small analytic test scenes built in memory.
#pragma once

#include "photoscene/core.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"

namespace ps::test {

inline Mat4d lookAt(const Vec3d& eye, const Vec3d& target, const Vec3d& up) {
  return io::lookAtWorldToCamera(eye, target, up);
}

inline int addPart(Scene& s, const std::string& name) {
  Part p;
  p.name = name;
  p.id = static_cast<int>(s.parts.size());
  s.parts.push_back(p);
  return p.id;
}

/// Appends a triangle with flat normals (winding normal) and the given corner uvs.
inline void addTriangle(Mesh& m, const Vec3f& a, const Vec3f& b, const Vec3f& c, int part,
                        const Vec2f& ua = Vec2f(0, 0), const Vec2f& ub = Vec2f(1, 0), const Vec2f& uc = Vec2f(0, 1)) {
  const int base = static_cast<int>(m.positions.size());
  m.positions.push_back(a);
  m.positions.push_back(b);
  m.positions.push_back(c);
  m.triangles.emplace_back(base, base + 1, base + 2);
  Vec3f n = (b - a).cross(c - a);
  n = n.norm() > 0 ? Vec3f(n.normalized()) : Vec3f(0, 0, 1);
  for (int k = 0; k < 3; ++k) m.cornerNormals.push_back(n);
  m.cornerUvs.push_back(ua);
  m.cornerUvs.push_back(ub);
  m.cornerUvs.push_back(uc);
  m.partIds.push_back(part);
  m.generatedUv.push_back(0);
}

/// Quad p, p + eu, p + eu + ev, p + ev (normal along eu x ev), uv = (0,0)..(su, sv).
inline void addQuad(Mesh& m, const Vec3f& p, const Vec3f& eu, const Vec3f& ev, int part, float su = 1, float sv = 1) {
  addTriangle(m, p, p + eu, p + eu + ev, part, Vec2f(0, 0), Vec2f(su, 0), Vec2f(su, sv));
  addTriangle(m, p, p + eu + ev, p + ev, part, Vec2f(0, 0), Vec2f(su, sv), Vec2f(0, sv));
}

/// UV sphere with smooth per-corner normals (outward, or inward with `inward`).
inline void addSphere(Mesh& m, const Vec3f& c, float r, int part, bool inward, int nTheta = 48, int nPhi = 96) {
  auto P = [&](int i, int j) {
    const float th = kPi * i / nTheta, ph = 2 * kPi * j / nPhi;
    return Vec3f(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
  };
  for (int i = 0; i < nTheta; ++i)
    for (int j = 0; j < nPhi; ++j) {
      const Vec3f a = P(i, j), b = P(i + 1, j), cc = P(i + 1, j + 1), d = P(i, j + 1);
      auto tri = [&](Vec3f x, Vec3f y, Vec3f z) {
        if (inward) std::swap(y, z);
        Vec3f fn = (y - x).cross(z - x);
        if (fn.norm() < 1e-9f) return;  // pole
        const int base = static_cast<int>(m.positions.size());
        for (const Vec3f& v : {x, y, z}) {
          m.positions.push_back(c + r * v);
          m.cornerNormals.push_back(inward ? Vec3f(-v) : v);
          m.cornerUvs.push_back(Vec2f(std::atan2(v.z(), v.x()) / (2 * kPi) + 0.5f, v.y() * 0.5f + 0.5f));
        }
        m.triangles.emplace_back(base, base + 1, base + 2);
        m.partIds.push_back(part);
        m.generatedUv.push_back(0);
      };
      // outward winding: (a, d, c) and (a, c, b) give normals pointing out
      tri(a, d, cc);
      tri(a, cc, b);
    }
}

inline PartMaterial lambert(const std::string& name, float albedo) {
  PartMaterial m = PartMaterial::defaultGray(name);
  m.albedo = Vec3f::Constant(albedo);
  m.roughness = 1.0f;
  m.specular = 0.0f;
  return m;
}

inline Camera makeCamera(int w, int h, double f, const Vec3d& eye, const Vec3d& target, const Vec3d& up = Vec3d(0, 1, 0)) {
  return Camera(w, h, f, f, (w - 1) / 2.0, (h - 1) / 2.0, lookAt(eye, target, up));
}

}  // namespace ps::test
