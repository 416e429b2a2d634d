// Small math: Eigen aliases and constants used across modules.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace ps {

using Vec2f = Eigen::Vector2f;
using Vec3f = Eigen::Vector3f;
using Vec4f = Eigen::Vector4f;
using Vec2d = Eigen::Vector2d;
using Vec3d = Eigen::Vector3d;
using Vec2i = Eigen::Vector2i;
using Mat3f = Eigen::Matrix3f;
using Mat3d = Eigen::Matrix3d;
using Mat4d = Eigen::Matrix4d;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr double kPiD = 3.14159265358979323846;

inline float radians(float deg) { return deg * (kPi / 180.0f); }
inline double radians(double deg) { return deg * (kPiD / 180.0); }
inline float degrees(float rad) { return rad * (180.0f / kPi); }
inline double degrees(double rad) { return rad * (180.0 / kPiD); }

template <typename T>
inline T clampv(T v, T lo, T hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}

/// i wrapped into [0, n) (n > 0): the texel of a periodic (tiling) map; -1 is n - 1.
inline int wrapIndex(int i, int n) {
  const int r = i % n;
  return r < 0 ? r + n : r;
}

/// True when every component of a fixed-size Eigen object is finite.
template <typename Derived>
inline bool allFinite(const Eigen::MatrixBase<Derived>& m) {
  return m.allFinite();
}

/// An orthonormal basis (t, b, n) around a unit vector n (Duff et al. 2017, branchless).
inline void orthonormalBasis(const Vec3f& n, Vec3f& t, Vec3f& b) {
  const float sign = std::copysign(1.0f, n.z());
  const float a = -1.0f / (sign + n.z());
  const float c = n.x() * n.y() * a;
  t = Vec3f(1.0f + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Vec3f(c, sign + n.y() * n.y() * a, -n.y());
}

}  // namespace ps
