// Lights of a scene: area emitters (an OBJ part, or a rectangle) and an environment.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"
#include "photoscene/io/scene_json.hpp"

namespace ps {

struct Mesh;

/// A one-sided area emitter with uniform radiance.
struct AreaLight {
  enum class Kind { Part, Rectangle };
  std::string name;
  Kind kind = Kind::Rectangle;
  int partId = -1;  ///< Kind::Part: the emitting part (its faces emit along their normals)
  /// Kind::Rectangle: spans center +- edgeU/2 +- edgeV/2, emits along normalize(edgeU x edgeV).
  Vec3f center = Vec3f::Zero(), edgeU = Vec3f::Zero(), edgeV = Vec3f::Zero();
  /// Emitted radiance (linear RGB, W / (m^2 sr) per channel); absent: to be fitted.
  std::optional<Vec3f> radiance;
  bool automatic = false;  ///< placed by the automatic ceiling grid

  /// Rectangle: unit emission direction.
  Vec3f normal() const { return edgeU.cross(edgeV).normalized(); }
  /// Rectangle area (m^2).
  float rectangleArea() const { return edgeU.cross(edgeV).norm(); }
};

/// Distant light from an equirectangular image (or a constant), optionally seen only through
/// window parts. For a unit direction d in the frame where up = +Y:
///   u = frac(0.5 + (atan2(d.z, d.x) - rotation) / 2pi),  v = 0.5 - asin(d.y) / pi  (v = 0 at top).
struct EnvironmentLight {
  cv::Mat image;                       ///< CV_32FC3 linear, or empty for a constant
  Vec3f radiance = Vec3f::Ones();      ///< multiplier on the image, or the constant radiance
  float rotationDeg = 0;
  std::vector<int> windowParts;        ///< part ids that are openings onto the environment
  Mat3f worldToEnv = Mat3f::Identity();  ///< rotation taking `up` onto +Y

  /// Radiance arriving from world direction `dir` (unit), bilinear in the image.
  Vec3f radianceFrom(const Vec3f& dir) const;
  /// (u, v) in [0, 1) x [0, 1] for a unit world direction.
  Vec2f directionToUv(const Vec3f& dir) const;
  /// Inverse of directionToUv.
  Vec3f uvToDirection(const Vec2f& uv) const;
};

struct LightSet {
  std::vector<AreaLight> area;
  std::optional<EnvironmentLight> environment;
};

/// Ceiling lights on a grid: the room's horizontal extent (the mesh's bounding box across `up`)
/// is split into ceil(extent / spacing) cells per axis, one square light of side `size` centered
/// in each, `offset` meters below the top of the box, facing down. A 6 x 4 m room at 3 m spacing
/// gets 2 x 2 lights.
std::vector<AreaLight> autoCeilingLights(const Mesh& mesh, const Vec3f& up, float spacing,
                                         float size = 0.5f, float offset = 0.01f);

}  // namespace ps
