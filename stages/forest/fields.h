// Scalar fields over the forest's ground: the terrain's height map and the density map
// (issue 13, "beyond Celba": Celba §4.5.4 names terrain elevation as the missing improvement).
//
// A field is a grid of samples in [0, 1] (an image's grey value: 16-bit PNG, EXR, ... read by the
// stage adapter) laid over the rectangle [x0, x1] x [z0, z1] of the ground: column c is at
// x0 + c (x1 - x0) / (cols - 1), row r (image row, top first) at z0 + r (z1 - z0) / (rows - 1),
// so the image's top edge is the forest's -Z side ("north" when -Z is north, as seen from above
// with +X to the right). Values between samples are bilinear; outside the rectangle the edge
// value holds (clamped).
#pragma once

#include <array>
#include <vector>

namespace sylva::forest {

struct Field {
  int cols = 0, rows = 0;     // >= 2 each when the field is used
  std::vector<float> values;  // rows * cols, row-major, in [0, 1]
  double x0 = 0, z0 = 0, x1 = 1, z1 = 1;

  bool empty() const { return values.empty(); }
  // Bilinear sample at (x, z), clamped to the rectangle.
  double sample(double x, double z) const;
};

// A height map: h(x, z) = height_min + (height_max - height_min) * field(x, z), metres.
struct Terrain {
  Field field;
  double height_min = 0, height_max = 0;

  bool empty() const { return field.empty(); }
  double height(double x, double z) const;
  // Slope of the bilinear surface, degrees in [0, 90): atan of the gradient's length, the gradient
  // by central differences one sample spacing wide.
  double slope_deg(double x, double z) const;
};

}  // namespace sylva::forest
