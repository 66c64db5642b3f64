// Internodes and internode merging.
//
// Seed: Zhang et al. 2017 (Tree Branch LOD Models for Forest Navigation), §4.1–4.4 and
// Appendix A.1–A.3: a branch is a list of skeletal vectors G_k = (P_k, R_k; T_k, N_k, B_k); the
// internode I_k is the ruled surface of eq. (1) between G_k and G_{k+1}; a run of internodes
// U_{k,q+2} is replaced by the single internode I_{k,q+2} when the explicit errors of eq. (3)–(5)
// stay under E1 (positional, phi) and E2 (radius/frame, varphi) and the torsion stays under Γ.
//
// Everything here is pure: plain data in, plain data out, no I/O.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "libs/tree/tree.h"
#include "libs/tree/vec3.h"

namespace sylva::lod {

using tree::Vec3;

// G_k plus the arc length t_k from the branch base (eq. 1) and the node angle beta_k (§4.2).
struct SkeletalVector {
  Vec3 p;           // P_k, m
  double r = 0;     // R_k, m
  Vec3 t, n, b;     // Frenet frame (A1), orthonormal, t x n = b
  double arc = 0;   // t_k, m
  double beta = 0;  // node angle, rad (0 at both ends)
};

// One branch of the tree as skeletal vectors. For a non-root branch the attachment point on
// its bearer is prepended (radius of the branch's first node), so the implicit segment from the
// bearer to nodes[0] (tree.h) is part of the branch surface.
struct BranchSkeleton {
  std::int32_t parent = -1;  // bearer branch index or -1
  double attach_arc = 0;     // arc length t on the bearer's skeleton where the branch grows, m
  std::vector<SkeletalVector> g;
};

// Skeletal vectors of every branch, indexed like tree.branches. Frames: libs/tree
// compute_frames (eq. A1), a child's N_0 continued from its bearer's frame. `tree` must be valid.
std::vector<BranchSkeleton> build_skeletons(const tree::Tree& tree);

// The explicit merging errors of replacing internodes k .. m-1 (m >= k + 1) by I_{k, m-k}.
struct MergeError {
  double phi = 0;      // eq. (3): max |X_{k,j}|, positional deviation of the inner nodes (m)
  double varphi = 0;   // eq. (3): sqrt(2) max(|Y_{k,j}|, |Z_{k,j}|), radius/frame deviation (m)
  double torsion = 0;  // sum of 2*beta_i over the inner nodes: bound (A2) on the frame turn (rad)
};

// Eq. (3)–(5) evaluated for the group U_{k, m-k}; all zero when m == k + 1 (nothing merged).
MergeError merge_error(std::span<const SkeletalVector> g, std::size_t k, std::size_t m);

struct MergeLimits {
  double e1 = 0;       // E1, m: bound on phi
  double e2 = 0;       // E2, m: bound on varphi
  double gamma = 1.0;  // Γ, rad: bound on the torsion of one merged internode
};

// Greedy internode merging along one branch (§4.4): from node k, the merged internode reaches a
// far node m whose group satisfies phi <= E1, varphi <= E2 and torsion <= Γ (eq. 3, A2; every
// taken group is checked in full). The end is found by an exponential then a binary search
// (internodes.cpp), O(L log L) for a group of L internodes, O(K log K) per branch of K
// internodes. Appends the indices of the kept nodes (always the first and the last) to `kept`;
// returns how many were appended. `check_cancelled` (may be empty) is called every 64 groups and
// may throw to stop.
std::size_t merge_internodes(std::span<const SkeletalVector> g, const MergeLimits& limits,
                             std::vector<std::uint32_t>& kept,
                             const std::function<void()>& check_cancelled = {});

// Value of the merged surface I_{k,m-k} (eq. 1 over the group, normals A3) at its parameter
// tau in [0, 1] and angle theta: the point the error bound (A6) compares with V(t, theta).
Vec3 merged_surface_point(std::span<const SkeletalVector> g, std::size_t k, std::size_t m, double tau,
                          double theta);

}  // namespace sylva::lod
