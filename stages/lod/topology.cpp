// Topology simplification by the accumulated bearer distance E4.
// Seed: Zhang et al. 2017, §5.3.
#include "stages/lod/topology.h"

#include <algorithm>
#include <limits>

namespace sylva::lod {

double distance_to_solid(std::span<const SkeletalVector> g, Vec3 p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < g.size(); ++k) {
    const Vec3 d = g[k + 1].p - g[k].p;
    const double dd = dot(d, d);
    const double u = dd > 0 ? std::clamp(dot(p - g[k].p, d) / dd, 0.0, 1.0) : 0.0;
    const Vec3 c = g[k].p + d * u;
    const double r = (1 - u) * g[k].r + u * g[k + 1].r;
    best = std::min(best, std::max(0.0, length(p - c) - r));
  }
  if (g.size() == 1) best = std::max(0.0, length(p - g[0].p) - g[0].r);
  return best;
}

std::vector<double> bearer_distances(std::span<const BranchSkeleton> skeletons) {
  std::vector<double> h(skeletons.size(), 0.0);
  for (std::size_t i = 0; i < skeletons.size(); ++i) {
    const BranchSkeleton& b = skeletons[i];
    if (b.parent < 0) continue;
    const auto& bearer = skeletons[static_cast<std::size_t>(b.parent)].g;
    double m = 0;
    for (const SkeletalVector& s : b.g) m = std::max(m, distance_to_solid(bearer, s.p) + s.r);
    h[i] = m;
  }
  return h;
}

std::vector<double> accumulated_distances(std::span<const BranchSkeleton> skeletons,
                                          std::span<const double> h) {
  const std::size_t n = skeletons.size();
  std::vector<double> below(n, 0.0);  // max over children of A(c)
  std::vector<double> a(n, 0.0);
  for (std::size_t i = n; i-- > 0;) {
    a[i] = h[i] + below[i];
    const std::int32_t p = skeletons[i].parent;
    if (p >= 0) below[static_cast<std::size_t>(p)] = std::max(below[static_cast<std::size_t>(p)], a[i]);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (skeletons[i].parent < 0) a[i] = std::numeric_limits<double>::infinity();
  return a;
}

std::vector<double> subtree_areas(std::span<const BranchSkeleton> skeletons,
                                  std::span<const char> drawn_by_cards) {
  const std::size_t n = skeletons.size();
  std::vector<double> area(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (i < drawn_by_cards.size() && drawn_by_cards[i]) continue;
    const auto& g = skeletons[i].g;
    for (std::size_t k = 0; k + 1 < g.size(); ++k)
      area[i] += (g[k].r + g[k + 1].r) * length(g[k + 1].p - g[k].p);
  }
  // Children come after their parents (tree.h): one backward pass accumulates the subtrees.
  for (std::size_t i = n; i-- > 0;) {
    const std::int32_t p = skeletons[i].parent;
    if (p >= 0) area[static_cast<std::size_t>(p)] += area[i];
  }
  return area;
}

std::vector<double> carried_alpha(std::span<const SkeletalVector> g, std::span<const std::uint32_t> kept,
                                  std::span<const std::pair<double, double>> deposits, double e3) {
  const std::size_t n = kept.size();
  std::vector<double> extra(n, 0.0);
  if (n < 2 || !(e3 > 0)) return extra;
  auto arc = [&](std::size_t j) { return g[kept[j]].arc; };
  for (const auto& [at, area] : deposits) {
    // The kept node nearest the attachment (ties: the lower one).
    std::size_t j = 0;
    while (j + 1 < n && arc(j + 1) <= at) ++j;
    if (j + 1 < n && arc(j + 1) - at < at - arc(j)) ++j;
    const double w = 0.5 * (arc(std::min(j + 1, n - 1)) - arc(j > 0 ? j - 1 : 0));
    if (w > 0) extra[j] += area / (e3 * w);
  }
  return extra;
}

}  // namespace sylva::lod
