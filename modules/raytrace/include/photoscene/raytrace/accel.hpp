// Ray queries against the scene mesh through an Embree 3 BVH (Embree 4 compiles too).
//
// Geometry 0 is the scene mesh (primitive = triangle index of ps::Mesh); geometry 1 holds the
// triangles lights add to the scene (Light::shapes(): a rectangle emitter is two), in the order
// given to the constructor. Build once per scene; queries are thread-safe.
//
//   std::vector<ps::Vec3f> shapes;  for (const ps::Light* l : scene.lights.all())
//   l->shapes(&shapes); ps::RayAccel accel(scene.mesh, shapes); ps::RayHit hit =
//   accel.intersect(origin, dir);   // hit.valid() ...
#pragma once

#include <memory>
#include <vector>

#include "photoscene/core/math.hpp"
#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/mesh.hpp"

namespace ps {

struct RayHit {
  float t = 0;       ///< distance along the (unit) direction
  int geom = -1;     ///< 0: mesh, 1: light shapes, -1: no hit
  int prim = -1;     ///< triangle index within the geometry
  float b1 = 0, b2 = 0;  ///< barycentrics: p = (1 - b1 - b2) p0 + b1 p1 + b2 p2
  bool valid() const { return geom >= 0; }
};

class RayAccel {
 public:
  /// Builds the BVH over `mesh` (kept by reference: it must outlive this) and the light shapes:
  /// triangles given as three consecutive vertices each.
  RayAccel(const Mesh& mesh, const std::vector<Vec3f>& shapeVertices);
  /// The same with the shapes of `lights` (their Light::shapes(), in order).
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
  /// The index into the constructor's `lights` of light-shape primitive `prim` (-1 when built
  /// from shape vertices).
  int rectangleLight(int prim) const {
    return prim < static_cast<int>(shapeLight_.size()) ? shapeLight_[prim] : -1;
  }
  /// Corners of light-shape triangle `prim`.
  void rectangleTriangle(int prim, Vec3f* p0, Vec3f* p1, Vec3f* p2) const;
  double buildSeconds() const { return buildSeconds_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  const Mesh& mesh_;
  void build(const std::vector<Vec3f>& shapeVertices);
  std::vector<int> shapeLight_;
  std::vector<Vec3f> shapeVertices_;
  double buildSeconds_ = 0;
};

}  // namespace ps
