#include "stages/forest/fields.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sylva::forest {

double Field::sample(double x, double z) const {
  if (values.empty()) return 1.0;
  const double u = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0) * (cols - 1);
  const double v = std::clamp((z - z0) / (z1 - z0), 0.0, 1.0) * (rows - 1);
  const int c0 = std::min(int(u), cols - 2), r0 = std::min(int(v), rows - 2);
  const double fu = u - c0, fv = v - r0;
  auto at = [&](int r, int c) { return double(values[std::size_t(r) * std::size_t(cols) + std::size_t(c)]); };
  const double top = at(r0, c0) * (1 - fu) + at(r0, c0 + 1) * fu;
  const double bottom = at(r0 + 1, c0) * (1 - fu) + at(r0 + 1, c0 + 1) * fu;
  return top * (1 - fv) + bottom * fv;
}

double Terrain::height(double x, double z) const {
  if (empty()) return 0.0;
  return height_min + (height_max - height_min) * field.sample(x, z);
}

double Terrain::slope_deg(double x, double z) const {
  if (empty()) return 0.0;
  const double hx = (field.x1 - field.x0) / (field.cols - 1), hz = (field.z1 - field.z0) / (field.rows - 1);
  const double gx = (height(x + hx, z) - height(x - hx, z)) / (2 * hx);
  const double gz = (height(x, z + hz) - height(x, z - hz)) / (2 * hz);
  return std::atan(std::hypot(gx, gz)) * 180 / std::numbers::pi;
}

}  // namespace sylva::forest
