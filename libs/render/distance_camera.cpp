// The checks' camera (distance_camera.h).
#include "libs/render/distance_camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace sylva::render {

namespace {

// Euclidean distance from p to the axis-aligned box b (0 inside).
double box_distance(const Bounds& b, const Eigen::Vector3d& p) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double lo = b.min[k], hi = b.max[k];
    const double e = p[k] < lo ? lo - p[k] : (p[k] > hi ? p[k] - hi : 0.0);
    s += e * e;
  }
  return std::sqrt(s);
}

}  // namespace

Camera camera_at_box_distance(const Bounds& bounds, double distance, double azimuth_deg, double elevation_deg,
                              double fov_y_rad, int height_px, int crop_px) {
  Bounds b = bounds;
  if (b.empty()) {
    b.extend(Vec3(-0.5f, -0.5f, -0.5f));
    b.extend(Vec3(0.5f, 0.5f, 0.5f));
  }
  const double a = azimuth_deg * std::numbers::pi / 180, e = elevation_deg * std::numbers::pi / 180;
  const Eigen::Vector3d dir(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
  const Eigen::Vector3d c = b.center().cast<double>();
  // The box distance grows monotonically along the ray once outside: bisect for the point at
  // exactly `distance` from the box.
  double lo = 0, hi = distance + 2.0 * b.radius() + 1.0;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (box_distance(b, c + mid * dir) < distance ? lo : hi) = mid;
  }
  Camera cam;
  cam.eye = (c + hi * dir).cast<float>();
  cam.target = c.cast<float>();
  cam.up = std::abs(dir.y()) > 0.999 ? Vec3::UnitZ() : Vec3::UnitY();
  double fov = fov_y_rad;
  if (crop_px > 0 && height_px > 0) fov = 2 * std::atan(std::tan(fov_y_rad / 2) * crop_px / height_px);
  cam.fov_y_deg = static_cast<float>(fov * 180 / std::numbers::pi);
  cam.z_near = static_cast<float>(std::max(1e-3, 0.5 * distance));
  cam.z_far = static_cast<float>(hi + 2.0 * b.radius() + 1.0);
  char buf[64];
  if (elevation_deg == 0) {
    std::snprintf(buf, sizeof buf, "az%g", azimuth_deg);
  } else {
    std::snprintf(buf, sizeof buf, "az%g_el%g", azimuth_deg, elevation_deg);
  }
  cam.name = buf;
  return cam;
}

}  // namespace sylva::render
