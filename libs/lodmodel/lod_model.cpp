// The LOD error model (lod_model.h; docs/lod-model.md). Each formula is written once, in the
// order of operations the pipeline's bytes were made with: pixel_size(camera, 1.0) is
// 2 tan(phi/2) / H to the bit, so a switch distance, its inverse and a distance scale agree with
// one another wherever they are computed.
#include "libs/lodmodel/lod_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sylva::lodmodel {

double radians(double deg) { return deg * std::numbers::pi / 180; }

double degrees(double rad) { return rad * 180 / std::numbers::pi; }

Camera camera_from_degrees(double fov_y_deg, int height_px) { return {radians(fov_y_deg), height_px}; }

double tan_half_fov(const Camera& camera) { return std::tan(camera.fov_y_rad / 2); }

double pixel_size(const Camera& camera, double distance) {
  return 2 * distance * tan_half_fov(camera) / camera.height_px;
}

double switch_distance(const Camera& camera, double epsilon, double delta) {
  return epsilon / (delta * pixel_size(camera, 1.0));
}

double spatial_error(const Camera& camera, double distance, double delta) {
  return distance * delta * pixel_size(camera, 1.0);
}

double switch_pixel_size(double epsilon, double delta) { return epsilon / delta; }

double distance_scale(const Camera& from, double from_delta, const Camera& to, double to_delta) {
  // The error a pixel budget allows at distance d is delta s(d) = delta d s(1): equal errors at
  // d_to and d_from when d_to = d_from (delta_from s_from(1)) / (delta_to s_to(1)).
  return (from_delta * pixel_size(from, 1.0)) / (to_delta * pixel_size(to, 1.0));
}

double screen_coverage(double tan_half_fov, double radius, double distance) {
  const double t = tan_half_fov;
  const double c = std::numbers::pi * radius * radius / ((2 * distance * t) * (2 * distance * t));
  // A loader never sees more than the whole screen: where the sphere overfills it, 1.
  return std::min(1.0, c);
}

double screen_coverage(const Camera& camera, double radius, double distance) {
  return screen_coverage(tan_half_fov(camera), radius, distance);
}

double coverage_distance(const Camera& camera, double radius, double coverage) {
  if (!(coverage > 0)) return std::numeric_limits<double>::infinity();
  return radius * std::sqrt(std::numbers::pi) / (2 * tan_half_fov(camera) * std::sqrt(coverage));
}

double coverage_tan_half_fov(double radius, double coverage, double distance) {
  return radius * std::sqrt(std::numbers::pi / coverage) / (2 * distance);
}

void BoundingBox::extend(double x, double y, double z) {
  const double p[3] = {x, y, z};
  for (int k = 0; k < 3; ++k) {
    lo_[k] = std::min(lo_[k], p[k]);
    hi_[k] = std::max(hi_[k], p[k]);
  }
}

void BoundingBox::extend(std::span<const float> xyz) {
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) extend(xyz[i], xyz[i + 1], xyz[i + 2]);
}

double BoundingBox::radius() const {
  if (empty()) return 0.0;
  return 0.5 * std::sqrt((hi_[0] - lo_[0]) * (hi_[0] - lo_[0]) + (hi_[1] - lo_[1]) * (hi_[1] - lo_[1]) +
                         (hi_[2] - lo_[2]) * (hi_[2] - lo_[2]));
}

double line_alpha(double coverage) {
  const double c = std::clamp(coverage, 0.0, 1.0);
  if (c >= 1) return 1.0;
  // 1 - (1 - c)^(1/3) without cancellation (c can be ~1e-16 for a needle line).
  return std::clamp(-std::expm1(std::log1p(-c) / 3), 0.0, 1.0);
}

double line_coverage(double alpha) { return -std::expm1(3 * std::log1p(-alpha)); }

double drawn_line_alpha(double eq12_alpha, double delta) { return line_alpha(eq12_alpha * delta); }

double line_alpha_at(double alpha, double scale) {
  if (!(alpha < 1)) return 1.0;
  return line_alpha(std::min(1.0, line_coverage(std::max(alpha, 0.0)) * scale));
}

}  // namespace sylva::lodmodel
