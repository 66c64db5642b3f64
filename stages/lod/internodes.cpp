// Internodes and internode merging.
// Seed: Zhang et al. 2017, §4.1–4.4 (eq. 1–5) and Appendix A.1–A.3 (eq. A1–A6).
#include "stages/lod/internodes.h"

#include <algorithm>
#include <cmath>

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
      initial_normal = bearer.g[std::min(bearer.g.size() - 1, br.parent_node + offset)].n;
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

std::size_t merge_internodes(std::span<const SkeletalVector> g, const MergeLimits& limits,
                             std::vector<std::uint32_t>& kept) {
  const std::size_t before = kept.size();
  const std::size_t last = g.size() - 1;
  std::size_t k = 0;
  kept.push_back(0);
  while (k < last) {
    // Extend the group while eq. (3) stays under E1/E2 and the torsion under Γ. The errors are
    // evaluated directly for each candidate end (no intermediate internodes are built).
    std::size_t m = k + 1;
    while (m < last) {
      const MergeError e = merge_error(g, k, m + 1);
      if (e.phi > limits.e1 || e.varphi > limits.e2 || e.torsion > limits.gamma) break;
      ++m;
    }
    kept.push_back(static_cast<std::uint32_t>(m));
    k = m;
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
