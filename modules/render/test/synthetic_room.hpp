// A small room built in memory for render-layer tests: floor, walls, ceiling, a box on the floor,
// one rectangular ceiling light; a camera looking down at the floor and the box.
#pragma once

#include <string>
#include <vector>

#include "photoscene/core.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/render.hpp"
#include "photoscene/scene.hpp"

namespace ps::testroom {

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

inline void addTriangle(Mesh& m, const Vec3f& a, const Vec3f& b, const Vec3f& c, int part, const Vec2f& ua,
                        const Vec2f& ub, const Vec2f& uc) {
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

struct Room {
  Scene scene;
  int floor = -1, walls = -1, ceiling = -1, box = -1;
  Camera camera;
};

/// uv of the floor and of the box's faces are metric (1 uv unit = 1 m).
inline Room makeRoom(int width, int height, float lightRadiance = 12.0f) {
  Room r;
  Scene& s = r.scene;
  r.floor = addPart(s, "floor");
  r.walls = addPart(s, "walls");
  r.ceiling = addPart(s, "ceiling");
  r.box = addPart(s, "box");
  Mesh& m = s.mesh;
  const float X = 4, Y = 2.5f, Z = 4;
  addQuad(m, Vec3f(0, 0, Z), Vec3f(X, 0, 0), Vec3f(0, 0, -Z), r.floor, X, Z);    // up
  addQuad(m, Vec3f(0, Y, 0), Vec3f(X, 0, 0), Vec3f(0, 0, Z), r.ceiling, X, Z);   // down
  addQuad(m, Vec3f(0, 0, 0), Vec3f(X, 0, 0), Vec3f(0, Y, 0), r.walls, X, Y);     // +z
  addQuad(m, Vec3f(X, 0, Z), Vec3f(-X, 0, 0), Vec3f(0, Y, 0), r.walls, X, Y);    // -z
  addQuad(m, Vec3f(0, 0, Z), Vec3f(0, 0, -Z), Vec3f(0, Y, 0), r.walls, Z, Y);    // +x
  addQuad(m, Vec3f(X, 0, 0), Vec3f(0, 0, Z), Vec3f(0, Y, 0), r.walls, Z, Y);     // -x
  // box 0.8 x 0.5 x 0.8 at (1.6..2.4, 0..0.5, 1.2..2.0): top and the four sides
  const float x0 = 1.6f, x1 = 2.4f, y1 = 0.5f, z0 = 1.2f, z1 = 2.0f;
  addQuad(m, Vec3f(x0, y1, z1), Vec3f(x1 - x0, 0, 0), Vec3f(0, 0, z0 - z1), r.box, x1 - x0, z1 - z0);  // top, +y
  addQuad(m, Vec3f(x0, 0, z1), Vec3f(x1 - x0, 0, 0), Vec3f(0, y1, 0), r.box, x1 - x0, y1);             // +z
  addQuad(m, Vec3f(x1, 0, z0), Vec3f(x0 - x1, 0, 0), Vec3f(0, y1, 0), r.box, x1 - x0, y1);             // -z
  addQuad(m, Vec3f(x1, 0, z1), Vec3f(0, 0, z0 - z1), Vec3f(0, y1, 0), r.box, z1 - z0, y1);             // +x
  addQuad(m, Vec3f(x0, 0, z0), Vec3f(0, 0, z1 - z0), Vec3f(0, y1, 0), r.box, z1 - z0, y1);             // -x
  AreaLight l;
  l.name = "ceiling";
  l.kind = AreaLight::Kind::Rectangle;
  l.center = Vec3f(2.6f, Y - 0.01f, 2.2f);
  l.edgeU = Vec3f(0.6f, 0, 0);
  l.edgeV = Vec3f(0, 0, 0.6f);  // u x v = -y: faces down
  l.radiance = Vec3f::Constant(lightRadiance);
  s.lights.area.push_back(l);
  const double f = 0.9 * width;
  r.camera = Camera(width, height, f, f, (width - 1) / 2.0, (height - 1) / 2.0,
                    lookAt(Vec3d(2.0, 1.7, 3.7), Vec3d(2.0, 0.2, 1.5), Vec3d(0, 1, 0)));
  return r;
}

inline PartMaterial lambert(const std::string& name, float albedo) {
  PartMaterial m = PartMaterial::defaultGray(name);
  m.albedo = Vec3f::Constant(albedo);
  m.roughness = 1.0f;
  m.specular = 0.0f;
  return m;
}

/// Everything the render layer needs of one view.
struct View {
  GBuffer gbuffer;
  IncidentLightGrid grid;
};

inline View prepareView(const PathTracer& tracer, const Camera& camera, int stride, int samplesPerBin, uint64_t seed) {
  View v;
  v.gbuffer = renderGBuffer(tracer, camera);
  IncidentLightOptions io;
  io.stride = stride;
  io.samplesPerBin = samplesPerBin;
  io.render.seed = seed;
  v.grid = computeIncidentLight(tracer, v.gbuffer, camera, io);
  return v;
}

}  // namespace ps::testroom
