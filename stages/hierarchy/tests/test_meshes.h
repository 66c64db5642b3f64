// Hand-built source geometry for the hierarchy tests: open tubes along polylines (a branch the
// way ez-tree or sylva's own mesh stage draws one: rings of vertices, no caps) and leaf quads
// (texture v 0 at the petiole, 1 at the tip).
#pragma once

#include <cmath>
#include <vector>

#include "libs/tree/source_geometry.h"
#include "libs/tree/vec3.h"

namespace sylva::hierarchy::testing {

using tree::Vec3;

// Appends an open tube: one ring of `segments` vertices per centre (radius radii[k]), quads
// between consecutive rings as two triangles, counter-clockwise seen from outside.
inline void add_tube(tree::SourcePrimitive& p, const std::vector<Vec3>& centres,
                     const std::vector<double>& radii, int segments = 12) {
  const auto first = static_cast<std::uint32_t>(p.positions.size());
  Vec3 u;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    const Vec3 t =
        normalized(k + 1 < centres.size() ? centres[k + 1] - centres[k] : centres[k] - centres[k - 1]);
    if (k == 0) {
      const Vec3 helper = std::abs(t.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
      u = normalized(cross(t, helper));
    } else {
      u = normalized(u - t * dot(u, t));  // parallel transport: no twist
    }
    const Vec3 w = cross(t, u);
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * M_PI * s / segments;
      p.positions.push_back(tree::to_float(centres[k] + (u * std::cos(a) + w * std::sin(a)) * radii[k]));
      p.uvs.push_back({static_cast<float>(s) / static_cast<float>(segments), static_cast<float>(k)});
    }
  }
  const auto n = static_cast<std::uint32_t>(segments);
  for (std::uint32_t k = 0; k + 1 < centres.size(); ++k)
    for (std::uint32_t s = 0; s < n; ++s) {
      const std::uint32_t a = first + k * n + s, b = first + k * n + (s + 1) % n;
      const std::uint32_t c = a + n, d = b + n;
      p.indices.insert(p.indices.end(), {a, b, d, a, d, c});
    }
}

// A straight tube from `base` along `dir` (unit) of `length`, radius tapering r0 -> r1, with
// `rings` rings.
inline void add_straight_tube(tree::SourcePrimitive& p, Vec3 base, Vec3 dir, double length, double r0,
                              double r1, int rings, int segments = 12) {
  std::vector<Vec3> c;
  std::vector<double> r;
  for (int k = 0; k < rings; ++k) {
    const double f = static_cast<double>(k) / (rings - 1);
    c.push_back(base + dir * (length * f));
    r.push_back(r0 + (r1 - r0) * f);
  }
  add_tube(p, c, r, segments);
}

// Appends a leaf quad from `petiole` along `dir` (length) and across `side` (width, centred).
inline void add_quad(tree::SourcePrimitive& p, Vec3 petiole, Vec3 dir, Vec3 side, double length,
                     double width) {
  const auto i = static_cast<std::uint32_t>(p.positions.size());
  const Vec3 h = side * (width / 2);
  p.positions.push_back(tree::to_float(petiole - h));
  p.positions.push_back(tree::to_float(petiole + h));
  p.positions.push_back(tree::to_float(petiole + h + dir * length));
  p.positions.push_back(tree::to_float(petiole - h + dir * length));
  p.uvs.insert(p.uvs.end(), {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  p.indices.insert(p.indices.end(), {i, i + 1, i + 2, i, i + 2, i + 3});
}

// The test tree: a vertical trunk (radius 0.2 -> 0.1, y 0..4), child `a` from inside the trunk at
// y = 2 going +x and up, child `b` at y = 3 going -x and up; a leaf quad at each child's tip.
struct TestTree {
  tree::SourceGeometry geometry;
};

inline tree::SourcePrimitive trunk_prim(const char* name) {
  tree::SourcePrimitive p;
  p.name = name;
  add_straight_tube(p, {0, 0, 0}, {0, 1, 0}, 4.0, 0.2, 0.1, 17);
  return p;
}
inline const Vec3 kDirA = normalized(Vec3{1, 0.5, 0});
inline const Vec3 kDirB = normalized(Vec3{-1, 0.6, 0});
inline tree::SourcePrimitive child_a(const char* name) {
  tree::SourcePrimitive p;
  p.name = name;
  add_straight_tube(p, {0.05, 2, 0}, kDirA, 1.5, 0.06, 0.03, 16);
  return p;
}
inline tree::SourcePrimitive child_b(const char* name) {
  tree::SourcePrimitive p;
  p.name = name;
  add_straight_tube(p, {-0.05, 3, 0}, kDirB, 1.2, 0.05, 0.025, 13);
  return p;
}
inline Vec3 tip_a() { return Vec3{0.05, 2, 0} + kDirA * 1.5; }
inline Vec3 tip_b() { return Vec3{-0.05, 3, 0} + kDirB * 1.2; }
inline tree::SourcePrimitive leaves(const char* name) {
  tree::SourcePrimitive p;
  p.name = name;
  p.material = 1;
  add_quad(p, tip_a(), {0, 1, 0}, {0, 0, 1}, 0.2, 0.1);
  add_quad(p, tip_b(), {0, 1, 0}, {0, 0, 1}, 0.2, 0.1);
  return p;
}

// Bark (opaque brown) and leaf (alpha-masked green) materials.
inline std::vector<tree::SourceMaterial> materials() {
  tree::SourceMaterial bark, leaf;
  bark.name = "bark";
  bark.base_color = {0.4f, 0.3f, 0.2f, 1};
  leaf.name = "leaf";
  leaf.base_color = {0.1f, 0.5f, 0.1f, 1};
  leaf.alpha_mode = tree::AlphaMode::kMask;
  return {bark, leaf};
}

// Celba's names: br0Trunk, br1a, br1b, lf1.
inline tree::SourceGeometry named_tree() {
  tree::SourceGeometry g;
  g.primitives = {trunk_prim("tree/br0Trunk"), child_a("tree/br1a"), child_b("tree/br1b"),
                  leaves("tree/lf1")};
  g.materials = materials();
  return g;
}

// No names: every branch in one merged primitive (ez-tree's layout), the leaves in another.
inline tree::SourceGeometry nameless_tree() {
  tree::SourcePrimitive bark = trunk_prim("tree/bark");
  for (const tree::SourcePrimitive& c : {child_a(""), child_b("")}) {
    const auto offset = static_cast<std::uint32_t>(bark.positions.size());
    bark.positions.insert(bark.positions.end(), c.positions.begin(), c.positions.end());
    bark.uvs.insert(bark.uvs.end(), c.uvs.begin(), c.uvs.end());
    for (std::uint32_t i : c.indices) bark.indices.push_back(i + offset);
  }
  tree::SourceGeometry g;
  g.primitives = {bark, leaves("tree/leaves")};
  g.materials = materials();
  return g;
}

}  // namespace sylva::hierarchy::testing
