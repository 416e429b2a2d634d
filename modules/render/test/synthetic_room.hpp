// A small room built in memory for render-layer tests: floor, walls, ceiling, a box on the floor,
// one rectangular ceiling light; a camera looking down at the floor and the box.
#pragma once

#include <string>
#include <vector>

#include "photoscene/core.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/render.hpp"
#include "photoscene/scene.hpp"
#include "../../raytrace/test/test_scenes.hpp"

namespace ps::testroom {

// the mesh-building helpers of the raytrace tests
using ps::test::addPart;
using ps::test::addQuad;
using ps::test::addTriangle;
using ps::test::lambert;
using ps::test::lookAt;

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


/// Path-tracer options of a reference render: `spp` samples, a one-pixel box filter.
inline RenderOptions boxFilterOptions(int spp, uint64_t seed) {
  RenderOptions ro;
  ro.spp = spp;
  ro.filter = PixelFilter::Box;
  ro.filterWidth = 1.0f;
  ro.seed = seed;
  return ro;
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
