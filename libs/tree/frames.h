// Rotation-minimising frames along branch skeletons and the node angle.
//
// Seed: Zhang et al. 2017, §4.2 and Appendix A.1, eq. (A1): the tangent T_k at a node is the
// bisector of the adjacent segment directions; the normal is propagated from node to node,
//   B_{k+1} = (T_{k+1} x N_k) / |T_{k+1} x N_k|,   N_{k+1} = B_{k+1} x T_{k+1},
// i.e. N_{k+1} is N_k projected onto the plane normal to T_{k+1}. The frames do not twist
// about the tangent beyond second order in the turning angle (a rotation-minimising frame), and
// Theorem 1 (A2) holds: T_k.T_{k+1}, N_k.N_{k+1}, B_k.B_{k+1} >= cos(beta_k + beta_{k+1}).
// The node angle is beta_k = arccos(L_k . L_{k-1}) / 2 (half the turn at node k), 0 at the ends.
//
// Frames are derived data: they are not stored in .sylt; every consumer recomputes them with
// these functions, so all stages agree on them bit for bit.
#pragma once

#include <span>
#include <vector>

#include "libs/tree/tree.h"
#include "libs/tree/vec3.h"

namespace sylva::tree {

// A right-handed orthonormal frame: t x n = b.
struct Frame {
  Vec3 t, n, b;
};

// Frames for one polyline (nodes.size() >= 1). `initial_normal` seeds N_0 (projected onto the
// plane normal to T_0; if it is parallel to T_0 an arbitrary perpendicular is used). Zero-length
// segments reuse the previous direction; a 180° reversal uses the incoming direction.
std::vector<Frame> compute_frames(std::span<const Node> nodes, Vec3 initial_normal);

// `f` carried to the unit tangent `t` by the minimal rotation taking f.t to t (Rodrigues);
// used to continue frames across a joint.
Frame transport_frame(const Frame& f, Vec3 t);

// beta_k in radians, one per node (0 at the first and last node).
std::vector<double> node_angles(std::span<const Node> nodes);

// Frames for every branch of a (valid) tree, indexed like tree.branches. A root starts from
// N = +X; a child starts from its parent's frame at parent_node carried to the
// child's first tangent by transport_frame(), so frames continue across joints.
std::vector<std::vector<Frame>> compute_tree_frames(const Tree& tree);

}  // namespace sylva::tree
