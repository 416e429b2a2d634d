// Pinhole camera, OpenCV convention: x right, y down, z forward; pixel (0, 0) is the center of
// the top-left pixel; K = [fx 0 cx; 0 fy cy; 0 0 1]; world_to_camera is rigid.
#pragma once

#include "photoscene/core/math.hpp"
#include "photoscene/io/scene_json.hpp"

namespace ps {

class Camera {
 public:
  Camera() = default;
  Camera(int width, int height, double fx, double fy, double cx, double cy, const Mat4d& worldToCamera);
  static Camera fromDesc(const io::CameraDesc& desc);
  io::CameraDesc toDesc() const;

  int width() const { return width_; }
  int height() const { return height_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  const Mat4d& worldToCamera() const { return worldToCamera_; }
  const Mat4d& cameraToWorld() const { return cameraToWorld_; }
  /// Camera center in world space.
  Vec3d position() const { return cameraToWorld_.topRightCorner<3, 1>(); }

  /// World point -> camera-space point.
  Vec3d toCamera(const Vec3d& world) const;
  /// Projects a world point to pixel coordinates. Returns false (pixel untouched) when the point
  /// is not in front of the camera (z <= 0). `depth` receives camera-space z.
  bool project(const Vec3d& world, Vec2d* pixel, double* depth = nullptr) const;
  /// The world point at camera-space depth z seen at `pixel`.
  Vec3d unproject(const Vec2d& pixel, double depth) const;
  /// Unit world-space direction of the ray through continuous pixel coordinates (x, y).
  Vec3d rayDirection(double x, double y) const;

  /// The same camera for an image of another size (same field of view; pixel-center
  /// convention kept: (c + 0.5) scales with the size).
  Camera resized(int width, int height) const;

 private:
  int width_ = 0, height_ = 0;
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0;
  Mat4d worldToCamera_ = Mat4d::Identity();
  Mat4d cameraToWorld_ = Mat4d::Identity();
};

}  // namespace ps
