// Foliage helpers (foliage.h): atlas layout, leaf area, crown projection, card-drawn twigs.
#include "libs/tree/foliage.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace sylva::tree {

UvRect atlas_cell(const Materials& m, unsigned variant) {
  const unsigned cols = std::max<unsigned>(1, m.atlas_columns), rows = std::max<unsigned>(1, m.atlas_rows);
  const unsigned cell = variant % (cols * rows);
  const unsigned c = cell % cols, r = cell / cols;
  const float du = 1.0f / static_cast<float>(cols), dv = 1.0f / static_cast<float>(rows);
  return {du * static_cast<float>(c), dv * static_cast<float>(r),
          c + 1 == cols ? 1.0f : du * static_cast<float>(c + 1),
          r + 1 == rows ? 1.0f : dv * static_cast<float>(r + 1)};
}

double cell_coverage(const Materials& m, unsigned variant) {
  if (m.cell_coverage.empty()) return 1.0;
  return m.cell_coverage[variant % m.cell_coverage.size()];
}

double leaf_area(const Materials& m, const Leaf& leaf) {
  return static_cast<double>(leaf.length) * static_cast<double>(leaf.width) * cell_coverage(m, leaf.variant);
}

double needle_area(const Needle& n) { return 2.0 * n.radius * length(to_double(n.tip) - to_double(n.base)); }

double convex_hull_area(std::vector<std::pair<double, double>> p) {
  // Akl–Toussaint: points strictly inside the octagon of the extreme points in eight directions
  // cannot be on the hull; dropping them first leaves a few per cent of a crown's points.
  if (p.size() > 64) {
    std::array<std::size_t, 8> ext{};
    auto key = [](const std::pair<double, double>& q, int d) {
      switch (d) {
        case 0:
          return q.first;
        case 1:
          return q.first + q.second;
        case 2:
          return q.second;
        case 3:
          return q.second - q.first;
        case 4:
          return -q.first;
        case 5:
          return -q.first - q.second;
        case 6:
          return -q.second;
        default:
          return q.first - q.second;
      }
    };
    for (std::size_t i = 1; i < p.size(); ++i)
      for (int d = 0; d < 8; ++d)
        if (key(p[i], d) > key(p[ext[d]], d)) ext[d] = i;
    std::vector<std::pair<double, double>> poly;
    for (int d = 0; d < 8; ++d)
      if (poly.empty() || poly.back() != p[ext[d]]) poly.push_back(p[ext[d]]);
    while (poly.size() > 1 && poly.back() == poly.front()) poly.pop_back();
    if (poly.size() >= 3) {
      auto inside = [&](const std::pair<double, double>& q) {
        for (std::size_t i = 0; i < poly.size(); ++i) {
          const auto& a = poly[i];
          const auto& b = poly[(i + 1) % poly.size()];
          if ((b.first - a.first) * (q.second - a.second) - (b.second - a.second) * (q.first - a.first) <= 0)
            return false;
        }
        return true;
      };
      std::erase_if(p, inside);
    }
  }
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return 0.0;
  auto turn = [](const std::pair<double, double>& o, const std::pair<double, double>& a,
                 const std::pair<double, double>& b) {
    return (a.first - o.first) * (b.second - o.second) - (a.second - o.second) * (b.first - o.first);
  };
  std::vector<std::pair<double, double>> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {  // lower hull
    while (k >= 2 && turn(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lo = k + 1; i-- > 0;) {  // upper hull
    while (k >= lo && turn(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  double a = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const auto& u = h[i];
    const auto& v = h[(i + 1) % h.size()];
    a += u.first * v.second - v.first * u.second;
  }
  return std::abs(a) / 2;
}

CrownFoliage crown_foliage(const Tree& tree) {
  CrownFoliage c;
  std::vector<std::pair<double, double>> pts;
  pts.reserve(4 * tree.leaves.size() + 2 * tree.needles.size());
  for (const Leaf& l : tree.leaves) {
    c.leaf_area += leaf_area(tree.materials, l);
    const Vec3 p = to_double(l.position), d = to_double(l.direction), n = to_double(l.normal);
    const Vec3 side = cross(n, d) * (0.5 * l.width), along = d * static_cast<double>(l.length);
    for (const Vec3 q : {p - side, p + side, p + along + side, p + along - side}) pts.emplace_back(q.x, q.z);
  }
  for (const Needle& n : tree.needles) {
    c.leaf_area += needle_area(n);
    pts.emplace_back(n.base.x, n.base.z);
    pts.emplace_back(n.tip.x, n.tip.z);
  }
  c.crown_area = convex_hull_area(std::move(pts));
  return c;
}

std::vector<char> twigs_drawn_by_cards(const Tree& tree) {
  if (tree.materials.leaf_kind == LeafKind::kLeaves) return {};
  std::vector<char> drawn(tree.branches.size(), 0);
  for (const Leaf& l : tree.leaves) {
    if (l.branch >= drawn.size() || tree.branches[l.branch].nodes.empty()) continue;
    // A card whose base lies within its own length of the twig's first node: the cards reach the
    // twig's base, so they draw all of it.
    const Vec3 d = to_double(l.position) - tree.branches[l.branch].nodes.front().position;
    if (length(d) <= static_cast<double>(l.length)) drawn[l.branch] = 1;
  }
  for (const Branch& b : tree.branches)
    if (b.parent >= 0) drawn[static_cast<std::size_t>(b.parent)] = 0;
  return drawn;
}

}  // namespace sylva::tree
