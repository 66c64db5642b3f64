// Internodes and internode merging.
// Seed: Zhang et al. 2017, §4.1–4.4 (eq. 1–5) and Appendix A.1–A.3 (eq. A1–A6).
#include "stages/lod/internodes.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "libs/tree/frames.h"

namespace sylva::lod {

namespace {

// Builds one skeleton from a node list and an initial normal (frames by eq. A1).
void fill_skeleton(std::span<const tree::Node> nodes, Vec3 initial_normal, BranchSkeleton& out) {
  const std::vector<tree::Frame> frames = tree::compute_frames(nodes, initial_normal);
  const std::vector<double> beta = tree::node_angles(nodes);
  out.g.resize(nodes.size());
  double arc = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    if (k > 0) arc += length(nodes[k].position - nodes[k - 1].position);
    SkeletalVector& s = out.g[k];
    s.p = nodes[k].position;
    s.r = nodes[k].radius;
    s.t = frames[k].t;
    s.n = frames[k].n;
    s.b = frames[k].b;
    s.arc = arc;
    s.beta = beta[k];
  }
}

}  // namespace

std::vector<BranchSkeleton> build_skeletons(const tree::Tree& tree) {
  std::vector<BranchSkeleton> out(tree.branches.size());
  std::vector<tree::Node> nodes;
  for (std::size_t i = 0; i < tree.branches.size(); ++i) {
    const tree::Branch& br = tree.branches[i];
    out[i].parent = br.parent;
    nodes.clear();
    Vec3 initial_normal{1, 0, 0};
    if (br.parent >= 0) {
      // The implicit segment from the attachment point to nodes[0] belongs to the branch.
      const Vec3 a = tree::attachment_point(tree, br);
      if (length(br.nodes.front().position - a) > 1e-9) nodes.push_back({a, br.nodes.front().radius});
      const BranchSkeleton& bearer = out[static_cast<std::size_t>(br.parent)];
      // The bearer's skeleton may have a prepended node: its node j is skeleton node j + offset.
      const std::size_t offset =
          bearer.g.size() - tree.branches[static_cast<std::size_t>(br.parent)].nodes.size();
      const std::size_t j = std::min(bearer.g.size() - 1, br.parent_node + offset);
      initial_normal = bearer.g[j].n;
      const double seg = j + 1 < bearer.g.size() ? bearer.g[j + 1].arc - bearer.g[j].arc : 0.0;
      out[i].attach_arc = bearer.g[j].arc + br.parent_t * seg;
    }
    nodes.insert(nodes.end(), br.nodes.begin(), br.nodes.end());
    fill_skeleton(nodes, initial_normal, out[i]);
  }
  return out;
}

MergeError merge_error(std::span<const SkeletalVector> g, std::size_t k, std::size_t m) {
  MergeError e;
  const SkeletalVector& a = g[k];
  const SkeletalVector& z = g[m];
  const double span_len = z.arc - a.arc;
  double yz = 0;
  for (std::size_t i = k + 1; i < m; ++i) {
    const SkeletalVector& s = g[i];
    // eq. (5): tau_{k,j} from arc lengths (j = i - k - 1).
    const double tau = span_len > 0 ? (s.arc - a.arc) / span_len : 0.5;
    // eq. (4)
    const Vec3 x = (1 - tau) * a.p + tau * z.p - s.p;
    const Vec3 y = (1 - tau) * a.r * a.n + tau * z.r * z.n - s.r * s.n;
    const Vec3 zz = (1 - tau) * a.r * a.b + tau * z.r * z.b - s.r * s.b;
    e.phi = std::max(e.phi, length(x));
    yz = std::max({yz, length(y), length(zz)});
    e.torsion += 2 * s.beta;
  }
  e.varphi = std::sqrt(2.0) * yz;  // eq. (3)
  return e;
}

namespace {

// Whether the group k .. m satisfies eq. (3) under E1/E2 -- merge_error() with an early exit at
// the first inner node that breaks a bound (the torsion is checked by the caller).
bool group_within(std::span<const SkeletalVector> g, std::size_t k, std::size_t m,
                  const MergeLimits& limits) {
  const SkeletalVector& a = g[k];
  const SkeletalVector& z = g[m];
  const double span_len = z.arc - a.arc;
  for (std::size_t i = k + 1; i < m; ++i) {
    const SkeletalVector& s = g[i];
    const double tau = span_len > 0 ? (s.arc - a.arc) / span_len : 0.5;
    const Vec3 x = (1 - tau) * a.p + tau * z.p - s.p;
    if (length(x) > limits.e1) return false;
    const Vec3 y = (1 - tau) * a.r * a.n + tau * z.r * z.n - s.r * s.n;
    const Vec3 zz = (1 - tau) * a.r * a.b + tau * z.r * z.b - s.r * s.b;
    if (std::sqrt(2.0) * std::max(length(y), length(zz)) > limits.e2) return false;  // as merge_error()
  }
  return true;
}

}  // namespace

std::size_t merge_internodes(std::span<const SkeletalVector> g, const MergeLimits& limits,
                             std::vector<std::uint32_t>& kept, const std::function<void()>& check_cancelled) {
  const std::size_t before = kept.size();
  const std::size_t last = g.size() - 1;
  // Torsion of a group k..m = sum of 2 beta over its inner nodes: prefix sums make it O(1), and
  // since it only grows with m, it caps every search below.
  std::vector<double> twice_beta(g.size() + 1, 0.0);
  for (std::size_t i = 0; i < g.size(); ++i) twice_beta[i + 1] = twice_beta[i] + 2 * g[i].beta;
  auto torsion = [&](std::size_t k, std::size_t m) { return twice_beta[m] - twice_beta[k + 1]; };
  auto valid = [&](std::size_t k, std::size_t m) {
    return torsion(k, m) <= limits.gamma && group_within(g, k, m, limits);
  };
  std::size_t k = 0, steps = 0;
  kept.push_back(0);
  while (k < last) {
    // 1. Exponential search: ends k + 2, k + 4, k + 8, ... while the group is valid (each check
    //    O(group length)). 2. Binary search between the last valid end and the first invalid one,
    //    keeping a valid end. The group taken is always checked in full by eq. (3) and the torsion
    //    bound; unlike extending one node at a time it may pass over an invalid intermediate end
    //    (the errors are not monotone in m), and it costs O(L log L) for a group of L internodes
    //    instead of O(L^2).
    std::size_t good = k + 1;  // one internode: always valid (nothing merged)
    std::size_t step = 1, bad = last + 1;
    while (good < last) {
      const std::size_t m = std::min(last, k + 2 * step);
      if (!valid(k, m)) {
        bad = m;
        break;
      }
      good = m;
      step *= 2;
    }
    while (bad - good > 1 && good < last) {
      const std::size_t mid = good + (bad - good) / 2;
      if (valid(k, mid)) {
        good = mid;
      } else {
        bad = mid;
      }
    }
    kept.push_back(static_cast<std::uint32_t>(good));
    k = good;
    if (check_cancelled && (++steps & 63) == 0) check_cancelled();
  }
  return kept.size() - before;
}

Vec3 merged_surface_point(std::span<const SkeletalVector> g, std::size_t k, std::size_t m, double tau,
                          double theta) {
  const SkeletalVector& a = g[k];
  const SkeletalVector& z = g[m];
  const double c = std::cos(theta), s = std::sin(theta);
  return (1 - tau) * a.p + tau * z.p + ((1 - tau) * a.r * a.n + tau * z.r * z.n) * c +
         ((1 - tau) * a.r * a.b + tau * z.r * z.b) * s;
}

}  // namespace sylva::lod
