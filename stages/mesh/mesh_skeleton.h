// The meshing skeleton: the tree (libs/tree) normalised into what the box-joint mesher walks —
// Nystad's DAG (§4.3.1, §5.3.1): per branch an ordered list of cross-sections ("rings") with
// centre, rotation-minimising frame, radius and texture v, and per ring the child branches that
// grow from it.
//
// Seeds: Nystad 2010 §4.3.1 (tree data -> DAG: object-space nodes with orientation, up vector,
// radius, level, children), §4.2.2 (a child hangs from an intermediate node of its parent),
// §4.3.3 (v = distance / (0.2 + 0.8 r)); Zhang et al. 2017 eq. (A1) via libs/tree/frames.h.
//
// What the normalisation does (docs/stages/mesh.md, "From tree to rings"):
//   1. Branches above `max_level` are left out (with everything growing from them), and so are
//      the branches `omit` names (childless twigs that their cards draw, libs/tree/foliage.h).
//   2. A child attached inside a segment (parent_t in (0.1, 0.9)) gets a virtual ring inserted
//      into its parent at the attachment point; otherwise it hangs from the nearer node.
//   3. Junction collapse: a ring whose children are all thinner than the continuation (they
//      will sit on the sides of a joint box) is removed and its children hang from the ring
//      before it — unless that ring has children itself. For generated trees this is Nystad's
//      DAG exactly: the junction node lies between the prepended and appended nodes (§4.2.2),
//      the child hangs from the prepended one, and the box (prepended -> appended) is centred
//      on the child. Without it the child would sit on the lower edge of its box.
//      A ring closer than 2 % of its corner distance to the previous ring is merged into it
//      (its children move along); such rings only make degenerate quads.
//      Radii below `min_radius` are raised to it (tapered tips reach 0).
//   4. Joint clearance: a child thinner than its parent's continuation will sit on a side face
//      of the parent's joint box (box_joints.h). Its rings that lie inside the box are dropped
//      while the next one is inside too; the first ring kept is moved along the child's first
//      segment to where it leaves the face it will join (or, for a one-ring child, along the
//      face's normal) so that it lies in front of that face. A child with no ring outside is dropped
//      and its own children re-attached to the ring it hung from. (Imported QSM trees start
//      children on the parent's axis; generated ones start outside, but at subdivision >= 1 the
//      box is larger than the branch, see corner_scale.)
//   5. Frames: each root starts from N = +X, each child from its parent's frame at the
//      attachment ring carried to the child's first tangent (as libs/tree's compute_tree_frames);
//      normals follow Zhang's rotation-minimising rule (eq. A1) but each tangent is the chord
//      over +-(corner distance) of arc length around the ring instead of the bisector of the
//      two adjacent segments, so rings closer than their size stay parallel and a bend at a
//      short segment does not fold the tube.
//   6. v grows with arc length divided by 2*pi*(0.2 r0 + 0.8 r) (r0: radius of the first root's
//      base), so one texture repeat is square on the trunk; a child continues the v of its
//      attachment ring plus the length of the joint segment.
//   3b. Ring thinning (SkeletonOptions::ring_tolerance): rings without a child whose removal
//      keeps the branch's axis and radius within the tolerance are left out.
//   7. A root's first ring is horizontal (frame t = +Y), so the foot stands flat on the ground
//      plane through its base node; with compensate_smoothing the ring radii are pre-compensated
//      for Catmull–Clark (SkeletonOptions).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "libs/tree/frames.h"
#include "libs/tree/tree.h"

namespace sylva::mesh {

using tree::Frame;
using tree::Vec3;

// The input tree cannot be meshed (empty, or breaks a libs/tree invariant). what() names the
// element, e.g. "branch 3: has 1 node (needs >= 2)".
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Ring {
  Vec3 center;
  Frame frame;               // t: branch direction; n, b span the cross-section
  double radius = 0;         // m, >= min_radius (the geometry)
  double source_radius = 0;  // m, the tree's radius (orders segments in a joint; may be 0)
  double v = 0;              // texture v at this ring (before the bark repeat factor)
};

struct SkeletonBranch {
  std::uint32_t source = 0;       // index into tree.branches
  std::int32_t parent = -1;       // index into MeshSkeleton::branches, -1 for a root
  std::uint32_t parent_ring = 0;  // ring of the parent it grows from
  std::uint32_t level = 0;
  bool clone = false;       // same level as its parent (a split)
  bool smooth = true;       // subdivided (SkeletonOptions::smooth_min_radius); else meshed flat
  std::vector<Ring> rings;  // base to tip, >= 1
};

struct SkeletonStats {
  std::size_t branches_in = 0;          // branches of the tree at levels <= max_level
  std::size_t virtual_rings = 0;        // rings inserted at mid-segment attachments
  std::size_t collapsed_junctions = 0;  // attachment rings removed so the box centres on the child
  std::size_t merged_rings = 0;         // rings within 2 % of their corner distance of the previous
  std::size_t clamped_radii = 0;        // node radii raised to min_radius
  std::size_t dropped_rings = 0;        // child rings inside the parent's joint box
  std::size_t pushed_rings = 0;         // first child rings moved out of the joint box
  std::size_t dropped_branches = 0;     // children entirely inside their parent
  std::size_t thinned_rings = 0;        // rings left out by ring_tolerance
};

struct MeshSkeleton {
  std::vector<SkeletonBranch> branches;  // parents before children
  // children[b][k]: skeleton branches growing from ring k of branch b, in tree order.
  std::vector<std::vector<std::vector<std::uint32_t>>> children;
  double v_unit = 1;  // 2*pi*r0: metres of a ring of radius r0 per unit of v
  SkeletonStats stats;

  std::size_t ring_count() const;
};

struct SkeletonOptions {
  int max_level = -1;         // highest branch level meshed; < 0 = all
  std::vector<char> omit;     // per tree branch, 1 = not meshed (twigs their cards draw); empty = none
  double min_radius = 0.001;  // m, > 0
  double corner_scale = 1.0;  // ring corner distance / radius (joint clearance uses it)
  // Pre-compensate Catmull–Clark's smoothing along each branch (subdivision >= 1): ring radii r^
  // solve (r^_{k-1} + 4 r^_k + r^_{k+1}) / 6 = r_k, the cubic B-spline limit of the ring
  // sequence, with the first and last ring kept; so the limit surface passes through the
  // skeleton's radii (a flared trunk foot keeps its width).
  bool compensate_smoothing = false;
  // Ring thinning of the branches that are not smooth (below) (m; 0 = keep every ring): a ring
  // with no meshed child, not next to a ring with one and not a branch's first or last is left out while the
  // straight segment between the kept rings around it passes within `ring_tolerance` of every left-out ring's
  // centre and the radius interpolated along it is within max(2 % of the ring's, ring_tolerance / 10).
  // Card-drawn twigs leave their parents' intermediate nodes (Nystad §4.2.2) without a child; on straight
  // stretches so are the generator's spacing nodes.
  double ring_tolerance = 0;
  // Branches whose first node is thinner than this (m; 0 = none) are not smooth: the mesher
  // leaves their quads unsubdivided (subdivision.h, subdivide_selected), so their rings get
  // `rough_scale` × the radius (corner_scale_for_subdivision(0) / corner_scale) and no
  // pre-compensation; a flat ring whose corners would come within 2.1 cm of the first root's
  // base (the generator keeps axes 1.5 r + 2 cm above it) is lifted by those millimetres.
  double smooth_min_radius = 0;
  double rough_scale = 1;
};

// Builds the meshing skeleton. Throws MeshError for an empty tree or one that fails
// tree::validate_tree (the first problems are listed). O(nodes + branches).
MeshSkeleton build_skeleton(const tree::Tree& tree, const SkeletonOptions& options);

}  // namespace sylva::mesh
