// Leaf collapse (FSA) and the foliage binary forest (VDF).
// Seed: Remolar et al. (FSA/VDF), §3 (leaf collapse cost, vertex placement) and §4 (binary forest).
#include "stages/lod/foliage.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "libs/tree/foliage.h"

namespace sylva::lod {

using tree::Vec3;

namespace {

double quad_area(const std::array<Vec3, 4>& v) { return 0.5 * length(cross(v[2] - v[0], v[3] - v[1])); }

// The collapse cost over cached per-leaf values (pair_merge.h's metric): the search evaluates
// ~24 candidates per step, and recomputing the centroid and sqrt(area) of 160-byte quads was
// most of the FSA time. The one definition of the cost (foliage.h); leaf_collapse_cost uses it.
struct LeafKey {
  Vec3 center, normal;
  double root_area;  // sqrt(A)
};

struct LeafMetric {
  LeafKey key(const LeafQuad& q) const { return {q.center(), q.normal, std::sqrt(q.area)}; }
  Vec3 center(const LeafKey& k) const { return k.center; }
  // The bound is not used for an early exit: the cost is cheap once cached.
  double cost(const LeafKey& a, const LeafKey& b, double /*bound*/) const {
    const double planarity = 0.5 * (a.root_area + b.root_area) * (1 - std::abs(dot(a.normal, b.normal)));
    return length(a.center - b.center) + planarity;
  }
  // cost >= the centroid distance; 1 - |n_a . n_b| may round to -1e-16, hence the slack (1 pm).
  double lower_bound(const LeafKey& /*a*/, double distance) const { return distance - 1e-12; }
};

}  // namespace

LeafQuad leaf_quad(const tree::Leaf& leaf, const tree::Materials& materials) {
  const Vec3 p = tree::to_double(leaf.position);
  const Vec3 d = tree::to_double(leaf.direction);
  const Vec3 n = tree::to_double(leaf.normal);
  const Vec3 side = normalized(cross(n, d)) * (0.5 * leaf.width);
  const Vec3 tip = p + d * static_cast<double>(leaf.length);
  LeafQuad q;
  // Counter-clockwise seen from +n. side = n x d points to the right of d seen from -n, so seen
  // from +n the corners run (p - side) -> (tip - side) -> (tip + side) -> (p + side); the other
  // order (p - side, p + side, ...) is clockwise and rendered every leaf dark in glTF clients.
  q.v = {p - side, tip - side, tip + side, p + side};
  // The variant's atlas cell (libs/tree's one definition, as the mesh stage uses it): u0 on the
  // -side edge, v0 at the petiole (or card base), v1 at the tip.
  const tree::UvRect c = tree::atlas_cell(materials, leaf.variant);
  q.uv = {{{c.u0, c.v0}, {c.u0, c.v1}, {c.u1, c.v1}, {c.u1, c.v0}}};
  q.normal = n;
  q.area = quad_area(q.v);
  return q;
}

double leaf_collapse_cost(const LeafQuad& a, const LeafQuad& b) {
  const LeafMetric m;
  return m.cost(m.key(a), m.key(b), std::numeric_limits<double>::infinity());
}

LeafQuad collapse_leaves(const LeafQuad& a, const LeafQuad& b) {
  const double target = a.area + b.area;
  const Vec3 mean_normal = a.normal * a.area + b.normal * b.area;
  // The new leaf shows one whole leaf of the atlas (the larger leaf's variant), the edge taken
  // from `a` as its petiole and the one from `b` as its tip. Keeping the corners' own uvs maps
  // a sliver of the atlas (two side edges), or parts of two variants, onto the quad, and the
  // alpha mask then cuts a shape that is no leaf.
  const LeafQuad& big = a.area >= b.area ? a : b;
  const float u0 = std::min({big.uv[0][0], big.uv[1][0], big.uv[2][0], big.uv[3][0]});
  const float v0 = std::min({big.uv[0][1], big.uv[1][1], big.uv[2][1], big.uv[3][1]});
  const float du = std::max({big.uv[0][0], big.uv[1][0], big.uv[2][0], big.uv[3][0]}) - u0;
  const float dv = std::max({big.uv[0][1], big.uv[1][1], big.uv[2][1], big.uv[3][1]}) - v0;
  const std::array<std::array<float, 2>, 4> uv = {
      {{u0, v0}, {u0 + du, v0}, {u0 + du, v0 + dv}, {u0, v0 + dv}}};
  LeafQuad best;
  double best_diff = std::numeric_limits<double>::infinity();
  for (int ea = 0; ea < 4; ++ea)
    for (int eb = 0; eb < 4; ++eb)
      for (int flip = 0; flip < 2; ++flip) {
        const int a0 = ea, a1 = (ea + 1) % 4;
        const int b0 = flip ? (eb + 1) % 4 : eb, b1 = flip ? eb : (eb + 1) % 4;
        LeafQuad q;
        q.v = {a.v[a0], a.v[a1], b.v[b0], b.v[b1]};
        q.uv = uv;
        q.area = quad_area(q.v);
        const double diff = std::abs(q.area - target);
        if (diff < best_diff) {
          best_diff = diff;
          best = q;
        }
      }
  Vec3 n = cross(best.v[2] - best.v[0], best.v[3] - best.v[1]);
  if (length(n) == 0) n = mean_normal;
  n = normalized(n);
  if (dot(n, mean_normal) < 0) {
    // Keep the front face on the pair's side: reverse the winding.
    std::swap(best.v[1], best.v[3]);
    std::swap(best.uv[1], best.uv[3]);
    n = -n;
  }
  best.normal = length(n) > 0 ? n : Vec3{0, 1, 0};
  return best;
}

LeafForest build_leaf_forest(std::span<const tree::Leaf> leaves, const tree::Materials& materials) {
  LeafForest lf;
  lf.quads.reserve(leaves.size() * 2);
  for (const tree::Leaf& l : leaves) lf.quads.push_back(leaf_quad(l, materials));
  lf.forest =
      agglomerate(lf.quads, LeafMetric{}, [](const LeafQuad& a, const LeafQuad& b, double ea, double eb) {
        return std::pair<LeafQuad, double>(collapse_leaves(a, b),
                                           std::max(ea, eb) + leaf_collapse_cost(a, b));
      });
  return lf;
}

void leaf_geometry(const LeafForest& forest, std::span<const std::uint32_t> active, LeafGeometry& out) {
  std::vector<LeafQuad> quads;
  quads.reserve(active.size());
  for (std::uint32_t id : active) quads.push_back(forest.quads[id]);
  leaf_geometry(quads, out);
}

void leaf_geometry(std::span<const LeafQuad> quads, LeafGeometry& out) {
  // One allocation per level instead of repeated growth (tens of thousands of leaves).
  out.positions.reserve(out.positions.size() + 12 * quads.size());
  out.normals.reserve(out.normals.size() + 12 * quads.size());
  out.texcoords.reserve(out.texcoords.size() + 8 * quads.size());
  out.indices.reserve(out.indices.size() + 6 * quads.size());
  for (const LeafQuad& q : quads) {
    const auto base = static_cast<std::uint32_t>(out.positions.size() / 3);
    for (int i = 0; i < 4; ++i) {
      out.positions.insert(out.positions.end(), {static_cast<float>(q.v[i].x), static_cast<float>(q.v[i].y),
                                                 static_cast<float>(q.v[i].z)});
      out.normals.insert(out.normals.end(), {static_cast<float>(q.normal.x), static_cast<float>(q.normal.y),
                                             static_cast<float>(q.normal.z)});
      out.texcoords.insert(out.texcoords.end(), {q.uv[i][0], q.uv[i][1]});
    }
    // Each triangle counter-clockwise around the leaf's normal: a collapsed leaf's four corners
    // come from two leaves and need not be planar, so one half of a folded quad can face away
    // (16 of 43,844 leaf triangles of a young oak's chain); glTF clients light such a triangle
    // from behind.
    for (const std::array<int, 3> t : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
      const Vec3 g = cross(q.v[t[1]] - q.v[t[0]], q.v[t[2]] - q.v[t[0]]);
      const bool flip = dot(g, q.normal) < 0;
      out.indices.insert(out.indices.end(),
                         {base + t[0], base + (flip ? t[2] : t[1]), base + (flip ? t[1] : t[2])});
    }
    ++out.leaves;
    out.area += q.area;
  }
}

}  // namespace sylva::lod
