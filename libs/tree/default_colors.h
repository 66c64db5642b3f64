// The colours every stage draws a tree with when its Materials give none (a Color of all zeros
// means "unset", as an imported TreeQSM tree has): one definition, so the mesh stage and the lod
// stage agree (issue 10: LODs of an imported tree were black where its mesh was brown).
#pragma once

#include <algorithm>
#include <array>

#include "libs/tree/tree.h"

namespace sylva::tree {

inline constexpr std::array<float, 4> kDefaultBarkColor{0.22f, 0.15f, 0.10f, 1};  // linear RGBA
inline constexpr std::array<float, 4> kDefaultLeafColor{0.10f, 0.30f, 0.05f, 1};
inline constexpr std::array<float, 4> kDefaultNeedleColor{0.08f, 0.22f, 0.06f, 1};  // needles use leaf_color

// `c` clamped to [0, 1] with alpha 1, or `fallback` when c is unset (all zero).
inline std::array<float, 4> color_or(const Color& c, const std::array<float, 4>& fallback) {
  if (c.r == 0 && c.g == 0 && c.b == 0) return fallback;
  auto clamp01 = [](float x) { return std::clamp(x, 0.0f, 1.0f); };
  return {clamp01(c.r), clamp01(c.g), clamp01(c.b), 1.0f};
}

inline std::array<float, 4> bark_color(const Materials& m) {
  return color_or(m.bark_color, kDefaultBarkColor);
}
inline std::array<float, 4> leaf_color(const Materials& m) {
  return color_or(m.leaf_color, kDefaultLeafColor);
}
inline std::array<float, 4> needle_color(const Materials& m) {
  return color_or(m.leaf_color, kDefaultNeedleColor);
}

}  // namespace sylva::tree
