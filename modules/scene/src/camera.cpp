#include "photoscene/scene/camera.hpp"

#include "photoscene/core/error.hpp"

namespace ps {

Camera::Camera(int width, int height, double fx, double fy, double cx, double cy, const Mat4d& w2c)
    : width_(width), height_(height), fx_(fx), fy_(fy), cx_(cx), cy_(cy), worldToCamera_(w2c) {
  PS_CheckGT(width, 0, "camera width");
  PS_CheckGT(height, 0, "camera height");
  PS_Check(fx > 0 && fy > 0, "focal lengths must be positive: " << fx << ", " << fy);
  const Mat3d r = w2c.topLeftCorner<3, 3>();
  cameraToWorld_.setIdentity();
  cameraToWorld_.topLeftCorner<3, 3>() = r.transpose();
  cameraToWorld_.topRightCorner<3, 1>() = -r.transpose() * w2c.topRightCorner<3, 1>();
}

Camera Camera::fromDesc(const io::CameraDesc& d) {
  return Camera(d.width, d.height, d.fx, d.fy, d.cx, d.cy, d.worldToCamera);
}

io::CameraDesc Camera::toDesc() const {
  io::CameraDesc d;
  d.width = width_;
  d.height = height_;
  d.fx = fx_;
  d.fy = fy_;
  d.cx = cx_;
  d.cy = cy_;
  d.worldToCamera = worldToCamera_;
  return d;
}

Vec3d Camera::toCamera(const Vec3d& world) const {
  return worldToCamera_.topLeftCorner<3, 3>() * world + worldToCamera_.topRightCorner<3, 1>();
}

bool Camera::project(const Vec3d& world, Vec2d* pixel, double* depth) const {
  const Vec3d c = toCamera(world);
  if (depth) *depth = c.z();
  if (!(c.z() > 0)) return false;
  if (pixel) *pixel = Vec2d(fx_ * c.x() / c.z() + cx_, fy_ * c.y() / c.z() + cy_);
  return true;
}

Vec3d Camera::unproject(const Vec2d& pixel, double depth) const {
  const Vec3d c((pixel.x() - cx_) / fx_ * depth, (pixel.y() - cy_) / fy_ * depth, depth);
  return cameraToWorld_.topLeftCorner<3, 3>() * c + cameraToWorld_.topRightCorner<3, 1>();
}

Vec3d Camera::rayDirection(double x, double y) const {
  const Vec3d c((x - cx_) / fx_, (y - cy_) / fy_, 1.0);
  return (cameraToWorld_.topLeftCorner<3, 3>() * c).normalized();
}

Camera Camera::resized(int width, int height) const {
  const double sx = static_cast<double>(width) / width_;
  const double sy = static_cast<double>(height) / height_;
  return Camera(width, height, fx_ * sx, fy_ * sy, (cx_ + 0.5) * sx - 0.5, (cy_ + 0.5) * sy - 0.5,
                worldToCamera_);
}

}  // namespace ps
