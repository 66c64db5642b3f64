// Conifer needle merging under E5.
// Seed: Zhang et al. 2017, §5.5.
#include "stages/lod/needles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sylva::lod {

using tree::Vec3;

namespace {

// b oriented like a (flipped when the directions disagree).
NeedleLine aligned(const NeedleLine& a, NeedleLine b) {
  if (dot(a.tip - a.base, b.tip - b.base) < 0) std::swap(b.base, b.tip);
  return b;
}

double disp(const NeedleLine& a, const NeedleLine& z) {
  const NeedleLine b = aligned(z, a);
  return std::max(length(b.base - z.base), length(b.tip - z.tip));
}

// The merging cost over cached per-needle values (pair_merge.h's metric), the one definition of
// the cost (needles.h); needle_cost uses it. Flipping b (aligned()) negates its direction and unit
// vector exactly and leaves its midpoint unchanged, so the cached form gives the same bits.
struct NeedleKey {
  Vec3 mid, dir, unit;  // (base + tip) / 2, tip - base, normalized(tip - base)
  std::uint32_t rank;
};

struct NeedleMetric {
  double mean_length;
  NeedleKey key(const NeedleLine& l) const {
    return {(l.base + l.tip) * 0.5, l.tip - l.base, normalized(l.tip - l.base), l.rank};
  }
  Vec3 center(const NeedleKey& k) const { return k.mid; }
  // The cost is (distance + angle) + rank with both first terms >= 0, and rounding is monotone,
  // so it is >= rank and >= distance + rank: once either passes the bound, the rest (the
  // square roots, the acos) is not needed (pair_merge.h: any value above the bound will do).
  double cost(const NeedleKey& a, const NeedleKey& b, double bound) const {
    const double rank = 1 - 2.0 / static_cast<double>(a.rank + b.rank);
    if (0.5 * rank > bound) return 0.5 * rank;
    const bool flip = dot(a.dir, b.dir) < 0;
    const double mismatch = 0.5 * std::max(length(flip ? a.dir + b.dir : a.dir - b.dir), 0.0);
    const double d = length(a.mid - b.mid) + 0.5 * mismatch;
    const double distance_term = 0.25 * d / std::max(mean_length, 1e-9);
    const double without_angle = distance_term + 0.5 * rank;
    if (without_angle > bound) return without_angle;
    const double angle = std::acos(std::clamp(std::abs(dot(a.unit, b.unit)), 0.0, 1.0));
    return distance_term + 0.25 * angle / (std::numbers::pi / 2) + 0.5 * rank;
  }
  // d >= the midpoint distance, and rank_b >= 1.
  double lower_bound(const NeedleKey& a, double distance) const {
    return 0.25 * distance / std::max(mean_length, 1e-9) + 0.5 * (1 - 2.0 / static_cast<double>(a.rank + 1));
  }
};

}  // namespace

double needle_cost(const NeedleLine& a, const NeedleLine& b, double mean_length) {
  const NeedleMetric m{mean_length};
  return m.cost(m.key(a), m.key(b), std::numeric_limits<double>::infinity());
}

NeedleLine merge_needles(const NeedleLine& a, const NeedleLine& b0) {
  const NeedleLine b = aligned(a, b0);
  const double wa = a.rank, wb = b.rank, w = wa + wb;
  NeedleLine z;
  z.base = (a.base * wa + b.base * wb) / w;
  z.tip = (a.tip * wa + b.tip * wb) / w;
  z.rank = a.rank + b.rank;
  const double l = length(z.tip - z.base);
  const double la = length(a.tip - a.base), lb = length(b.tip - b.base);
  z.radius = l > 0 ? (a.radius * la + b.radius * lb) / l : std::max(a.radius, b.radius);
  return z;
}

NeedleForest build_needle_forest(std::span<const tree::Needle> needles) {
  NeedleForest nf;
  nf.needles.reserve(needles.size() * 2);
  double total = 0;
  for (const tree::Needle& n : needles) {
    NeedleLine l{tree::to_double(n.base), tree::to_double(n.tip), n.radius, 1};
    total += length(l.tip - l.base);
    nf.needles.push_back(l);
  }
  nf.mean_length = needles.empty() ? 0 : total / static_cast<double>(needles.size());
  const double mean = nf.mean_length;
  nf.forest = agglomerate(nf.needles, NeedleMetric{mean},
                          [](const NeedleLine& a, const NeedleLine& b, double ea, double eb) {
                            NeedleLine z = merge_needles(a, b);
                            const double err = std::max(ea + disp(a, z), eb + disp(b, z));
                            return std::pair<NeedleLine, double>(z, err);
                          });
  return nf;
}

void needle_geometry(const NeedleForest& forest, std::span<const std::uint32_t> active, double e3,
                     int max_edges, BranchGeometry& out) {
  SkeletalVector g[2];
  const std::uint32_t kept[2] = {0, 1};
  for (std::uint32_t id : active) {
    const NeedleLine& l = forest.needles[id];
    const Vec3 t = normalized(l.tip - l.base);
    if (length(t) == 0) continue;
    const Vec3 helper = std::abs(t.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    const Vec3 n = normalized(cross(helper, t));
    const Vec3 b = cross(t, n);
    g[0] = {l.base, l.radius, t, n, b, 0, 0};
    g[1] = {l.tip, l.radius, t, n, b, length(l.tip - l.base), 0};
    polygonize_branch(g, kept, e3, std::min(max_edges, 3), out);
  }
}

}  // namespace sylva::lod
