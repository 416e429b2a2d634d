// Uniform solid-angle sampling of a rectangle seen from a point (Urena, Fajardo, King 2013,
// "An Area-Preserving Parametrization for Spherical Rectangles").
//
// The rectangle is corner + a ex + b ey, a, b in [0, 1], with ex perpendicular to ey. Seen from
// `o`, it covers the solid angle `solidAngle()` (steradians); `sample(u, v)` maps the unit square
// onto it with constant density 1 / solidAngle() in solid angle, and is continuous and
// monotone in u and v (stratified inputs stay stratified). Computed in double precision, so
// points close to the rectangle's plane (grazing views) stay accurate; callers should still
// fall back to area sampling when the solid angle is tiny (below ~1e-4 sr) or the setup
// reports invalid (o in the plane).
//
//   ps::SphericalRectangle sr(corner, ex, ey, x);
//   if (sr.valid() && sr.solidAngle() > 1e-4f) {
//     const ps::Vec3f y = sr.sample(u, v);      // a point on the rectangle
//     const float pdf = 1.0f / sr.solidAngle(); // per steradian, at x
//   }
#pragma once

#include <algorithm>
#include <cmath>

#include "photoscene/core/math.hpp"

namespace ps {

class SphericalRectangle {
 public:
  /// @param corner  a corner of the rectangle (world)
  /// @param ex, ey  its two edges from `corner` (perpendicular)
  /// @param o       the point it is seen from
  SphericalRectangle(const Vec3f& corner, const Vec3f& ex, const Vec3f& ey, const Vec3f& o) {
    const Vec3d s = corner.cast<double>(), exd = ex.cast<double>(), eyd = ey.cast<double>();
    o_ = o.cast<double>();
    const double exl = exd.norm(), eyl = eyd.norm();
    if (!(exl > 0) || !(eyl > 0)) return;
    x_ = exd / exl;
    y_ = eyd / eyl;
    z_ = x_.cross(y_);
    const Vec3d d = s - o_;
    z0_ = d.dot(z_);
    if (z0_ > 0) {  // z points away from the rectangle
      z_ = -z_;
      z0_ = -z0_;
    }
    if (!(std::abs(z0_) > 1e-9 * (exl + eyl))) return;  // o in the rectangle's plane
    x0_ = d.dot(x_);
    y0_ = d.dot(y_);
    x1_ = x0_ + exl;
    y1_ = y0_ + eyl;
    const Vec3d v00(x0_, y0_, z0_), v01(x0_, y1_, z0_), v10(x1_, y0_, z0_), v11(x1_, y1_, z0_);
    const Vec3d n0 = v00.cross(v10).normalized(), n1 = v10.cross(v11).normalized();
    const Vec3d n2 = v11.cross(v01).normalized(), n3 = v01.cross(v00).normalized();
    auto angle = [](double c) { return std::acos(std::clamp(c, -1.0, 1.0)); };
    const double g0 = angle(-n0.dot(n1)), g1 = angle(-n1.dot(n2)), g2 = angle(-n2.dot(n3)),
                 g3 = angle(-n3.dot(n0));
    b0_ = n0.z();
    b1_ = n2.z();
    k_ = 2 * kPiD - g2 - g3;
    S_ = g0 + g1 - k_;
    valid_ = S_ > 0 && std::isfinite(S_);
  }

  bool valid() const { return valid_; }
  /// Solid angle (steradians) of the rectangle seen from o; 0 when !valid().
  float solidAngle() const { return valid_ ? static_cast<float>(S_) : 0.0f; }
  /// Signed distance of o to the rectangle's plane (>= 0).
  double planeDistance() const { return -z0_; }

  /// A point on the rectangle; (u, v) uniform in [0, 1)^2 gives directions uniform in solid angle.
  Vec3f sample(float u, float v) const {
    const double au = u * S_ + k_;
    const double fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
    double cu = (fu > 0 ? 1.0 : -1.0) / std::sqrt(fu * fu + b0_ * b0_);
    cu = std::clamp(cu, -1.0, 1.0);
    double xu = -(cu * z0_) / std::sqrt(std::max(1e-300, 1 - cu * cu));
    xu = std::clamp(xu, x0_, x1_);
    const double dd = std::sqrt(xu * xu + z0_ * z0_);
    const double h0 = y0_ / std::sqrt(dd * dd + y0_ * y0_),
                 h1 = y1_ / std::sqrt(dd * dd + y1_ * y1_);
    const double hv = h0 + v * (h1 - h0), hv2 = hv * hv;
    double yv = hv2 < 1 - 1e-12 ? (hv * dd) / std::sqrt(1 - hv2) : y1_;
    yv = std::clamp(yv, y0_, y1_);
    return (o_ + xu * x_ + yv * y_ + z0_ * z_).cast<float>();
  }

 private:
  Vec3d o_ = Vec3d::Zero(), x_ = Vec3d::Zero(), y_ = Vec3d::Zero(), z_ = Vec3d::Zero();
  double z0_ = 0, x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0, b0_ = 0, b1_ = 0, k_ = 0, S_ = 0;
  bool valid_ = false;
};

}  // namespace ps
