// Zhang et al. 2017, Appendix A.1, eq. (A1): bisector tangents and propagated normals.
#include "libs/tree/frames.h"

#include <algorithm>
#include <cmath>

namespace sylva::tree {

namespace {

// Unit direction of every segment (size n - 1); a zero-length segment repeats the previous
// direction (or the next non-zero one at the start; +Y if all are zero).
std::vector<Vec3> segment_directions(std::span<const Node> nodes) {
  std::vector<Vec3> dirs(nodes.size() > 1 ? nodes.size() - 1 : 0);
  Vec3 last{};
  bool have = false;
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    const Vec3 d = nodes[k + 1].position - nodes[k].position;
    const double l = length(d);
    if (l > 0) {
      dirs[k] = d / l;
      if (!have) std::fill(dirs.begin(), dirs.begin() + static_cast<std::ptrdiff_t>(k), dirs[k]);
      last = dirs[k];
      have = true;
    } else {
      dirs[k] = have ? last : Vec3{};
    }
  }
  if (!have) std::fill(dirs.begin(), dirs.end(), Vec3{0, 1, 0});
  return dirs;
}

// Any unit vector perpendicular to unit t.
Vec3 any_perpendicular(Vec3 t) {
  const Vec3 axis = std::abs(t.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 0, 1};
  return normalized(cross(cross(t, axis), t));
}

}  // namespace

Frame transport_frame(const Frame& f, Vec3 t) {
  const Vec3 axis = cross(f.t, t);
  const double s = length(axis), c = dot(f.t, t);
  Vec3 n = f.n;
  if (s > 1e-15) {
    const Vec3 k = axis / s;  // Rodrigues: rotate by the angle between f.t and t about k
    n = f.n * c + cross(k, f.n) * s + k * (dot(k, f.n) * (1 - c));
  } else if (c < 0) {
    n = f.n;  // exact reversal: a half turn about N keeps N
  }
  n = normalized(n - t * dot(n, t));
  if (length(n) < 0.5) n = any_perpendicular(t);
  return {t, n, cross(t, n)};
}

std::vector<Frame> compute_frames(std::span<const Node> nodes, Vec3 initial_normal) {
  std::vector<Frame> frames(nodes.size());
  if (nodes.empty()) return frames;
  const std::vector<Vec3> dirs = segment_directions(nodes);
  const std::size_t n = nodes.size();
  // 1. Tangents: the bisector of the adjacent segment directions (one-sided at the ends).
  for (std::size_t k = 0; k < n; ++k) {
    Vec3 t;
    if (dirs.empty()) {
      t = {0, 1, 0};
    } else if (k == 0) {
      t = dirs.front();
    } else if (k == n - 1) {
      t = dirs.back();
    } else {
      const Vec3 s = dirs[k - 1] + dirs[k];
      t = length(s) > 1e-12 ? normalized(s) : dirs[k - 1];
    }
    frames[k].t = t;
  }
  // 2. N_0: the seed normal projected onto the plane normal to T_0.
  {
    const Vec3 t = frames[0].t;
    Vec3 nn = initial_normal - t * dot(initial_normal, t);
    nn = length(nn) > 1e-9 ? normalized(nn) : any_perpendicular(t);
    frames[0].n = nn;
    frames[0].b = cross(t, nn);
  }
  // 3. Propagation (A1): B_{k+1} = T_{k+1} x N_k normalised, N_{k+1} = B_{k+1} x T_{k+1}.
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const Vec3 t = frames[k + 1].t;
    Vec3 b = cross(t, frames[k].n);
    if (length(b) < 1e-12) b = frames[k].b - t * dot(frames[k].b, t);  // T_{k+1} parallel to N_k
    b = normalized(b);
    frames[k + 1].b = b;
    frames[k + 1].n = cross(b, t);
  }
  return frames;
}

std::vector<double> node_angles(std::span<const Node> nodes) {
  std::vector<double> beta(nodes.size(), 0.0);
  if (nodes.size() < 3) return beta;
  const std::vector<Vec3> dirs = segment_directions(nodes);
  for (std::size_t k = 1; k + 1 < nodes.size(); ++k)
    beta[k] = std::acos(std::clamp(dot(dirs[k], dirs[k - 1]), -1.0, 1.0)) / 2;
  return beta;
}

std::vector<std::vector<Frame>> compute_tree_frames(const Tree& tree) {
  std::vector<std::vector<Frame>> out(tree.branches.size());
  for (std::size_t i = 0; i < tree.branches.size(); ++i) {
    const Branch& b = tree.branches[i];
    Vec3 seed{1, 0, 0};
    if (b.parent >= 0) {
      // Carry the parent's frame at the joint to the child's first tangent by the minimal
      // rotation, so the child's N continues the parent's without an arbitrary twist.
      const Frame& pf = out[static_cast<std::size_t>(b.parent)][b.parent_node];
      if (b.nodes.size() >= 2) seed = transport_frame(pf, segment_directions(b.nodes).front()).n;
    }
    out[i] = compute_frames(b.nodes, seed);
  }
  return out;
}

}  // namespace sylva::tree
