// Compositing the bake's layers (bake_layers.h says what each holds).
#include "libs/render/bake_layers.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace sylva::render {
namespace {

std::uint8_t to8(double v) { return std::uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

}  // namespace

void composite_bake_texel(const std::uint16_t* packed, const std::uint16_t* line_color,
                          const std::uint16_t* line_normal, const std::uint16_t* line_depth,
                          std::uint8_t* color, std::uint8_t* normal_depth) {
  const bool opaque = (packed[3] >> 8) != 0;
  const std::uint8_t o8[8] = {std::uint8_t(packed[0] & 255), std::uint8_t(packed[0] >> 8),
                              std::uint8_t(packed[1] & 255), std::uint8_t(packed[1] >> 8),
                              std::uint8_t(packed[2] & 255), std::uint8_t(packed[2] >> 8),
                              std::uint8_t(packed[3] & 255), 0};
  if (line_color[3] == 0 && line_normal[3] == 0 && line_depth[3] == 0) {
    if (!opaque) return;
    // The opaque texel alone: its values as the shader rounded them.
    for (int c = 0; c < 3; ++c) color[c] = o8[c];
    color[3] = 255;
    for (int c = 0; c < 4; ++c) normal_depth[c] = o8[3 + c];
    return;
  }
  const double o = opaque ? 1.0 : 0.0;
  // Lines over the opaque texel: (line rgb + (1 - a) o v) / (a + (1 - a) o), each layer with
  // its own alpha (they are equal up to rounding).
  auto over = [&](const std::uint16_t* line, int channel, double opaque_value, double& coverage) {
    const double a = line[3] / 65535.0;
    coverage = a + (1 - a) * o;
    return (line[channel] / 65535.0 + (1 - a) * o * opaque_value) / coverage;
  };
  double coverage = 0;
  std::uint8_t rgb[3];
  for (int c = 0; c < 3; ++c) rgb[c] = to8(over(line_color, c, o8[c] / 255.0, coverage));
  // Coverage below half a level of the 8-bit alpha: not covered, as the maps store it.
  if (to8(coverage) == 0) return;
  for (int c = 0; c < 3; ++c) color[c] = rgb[c];
  color[3] = to8(coverage);
  // The mean normal, not renormalised (its length says how much the normals spread), at most 1.
  Eigen::Vector3d n;
  for (int c = 0; c < 3; ++c) n[c] = over(line_normal, c, o8[3 + c] / 255.0, coverage) * 2 - 1;
  if (n.norm() > 1) n.normalize();
  for (int c = 0; c < 3; ++c) normal_depth[c] = to8(n[c] * 0.5 + 0.5);
  normal_depth[3] = to8(over(line_depth, 0, o8[6] / 255.0, coverage));
}

}  // namespace sylva::render
