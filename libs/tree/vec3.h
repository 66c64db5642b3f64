// Small 3-vectors for the tree model: plain aggregates, no alignment or expression templates,
// so they can be memcpy'd, compared with == and written field by field to .sylt.
//
// Vec3 (double) is used for the skeleton; Vec3f (float) for foliage, where there are many
// elements and float precision (~0.1 mm at 1 km) is ample. Code that wants Eigen can map them:
//   Eigen::Map<const Eigen::Vector3d>(&v.x) works because the three members are contiguous.
// Units are whatever the owner states (metres for every position in libs/tree).
#pragma once

#include <cmath>

namespace sylva::tree {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  friend constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend constexpr Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
  friend constexpr Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
  friend constexpr Vec3 operator*(double s, Vec3 a) { return a * s; }
  friend constexpr Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
  constexpr Vec3& operator+=(Vec3 b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
  constexpr Vec3& operator-=(Vec3 b) {
    x -= b.x;
    y -= b.y;
    z -= b.z;
    return *this;
  }
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3 a) { return std::sqrt(dot(a, a)); }
// a / |a|; the zero vector stays zero (callers that can meet it check length first).
inline Vec3 normalized(Vec3 a) {
  const double l = length(a);
  return l > 0 ? a / l : a;
}
inline bool is_finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

struct Vec3f {
  float x = 0, y = 0, z = 0;
  friend constexpr bool operator==(const Vec3f&, const Vec3f&) = default;
};

constexpr Vec3f to_float(Vec3 v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}
constexpr Vec3 to_double(Vec3f v) { return {v.x, v.y, v.z}; }
inline bool is_finite(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

}  // namespace sylva::tree
