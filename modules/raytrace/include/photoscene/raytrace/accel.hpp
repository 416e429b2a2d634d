// Ray queries against the scene mesh through an Embree 3 BVH (Embree 4 compiles too).
//
// Geometry 0 is the scene mesh (primitive = triangle index of ps::Mesh); geometry 1 holds the
// rectangle emitters, two triangles each (primitive 2 i and 2 i + 1 belong to rectangle i of
// the list given to the constructor). Build once per scene; queries are thread-safe.
//
//   ps::RayAccel accel(scene.mesh, rectangles);
//   ps::RayHit hit = accel.intersect(origin, dir);   // hit.valid() ...
#pragma once

#include <memory>
#include <vector>

#include "photoscene/core/math.hpp"
#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/mesh.hpp"

namespace ps {

struct RayHit {
  float t = 0;       ///< distance along the (unit) direction
  int geom = -1;     ///< 0: mesh, 1: rectangle emitters, -1: no hit
  int prim = -1;     ///< triangle index within the geometry
  float b1 = 0, b2 = 0;  ///< barycentrics: p = (1 - b1 - b2) p0 + b1 p1 + b2 p2
  bool valid() const { return geom >= 0; }
};

class RayAccel {
 public:
  /// Builds the BVH over `mesh` (kept by reference: it must outlive this) and the rectangles
  /// among `lights` (kind Rectangle; others are ignored).
  explicit RayAccel(const Mesh& mesh, const std::vector<AreaLight>& lights = {});
  ~RayAccel();
  RayAccel(const RayAccel&) = delete;
  RayAccel& operator=(const RayAccel&) = delete;

  /// Closest hit along org + t dir, t in (tnear, tfar). `dir` must be unit length.
  RayHit intersect(const Vec3f& org, const Vec3f& dir, float tnear = 0.0f,
                   float tfar = std::numeric_limits<float>::infinity()) const;
  /// True when anything lies along org + t dir, t in (tnear, tfar).
  bool occluded(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const;

  const Mesh& mesh() const { return mesh_; }
  /// The index into the constructor's `lights` of rectangle-emitter primitive `prim`.
  int rectangleLight(int prim) const { return rectLightIndex_[prim / 2]; }
  /// Corners of rectangle-emitter triangle `prim`.
  void rectangleTriangle(int prim, Vec3f* p0, Vec3f* p1, Vec3f* p2) const;
  double buildSeconds() const { return buildSeconds_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  const Mesh& mesh_;
  std::vector<int> rectLightIndex_;
  std::vector<Vec3f> rectVertices_;
  double buildSeconds_ = 0;
};

}  // namespace ps
