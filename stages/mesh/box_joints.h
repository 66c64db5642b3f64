// The bark mesh: one closed quad mesh for every meshed branch, connected at every joint by the
// recursive box `Connect` of Nystad 2010, Appendix D.
//
// Seeds: Nystad 2010 §3.3 (one connected mesh, four-vertex cross-sections, Fig. 3.2), §3.3.2 and
// §4.3.3 (three connection cases; all remaining branches sorted onto the four box sides and
// handled recursively), Appendix D (Connect pseudo code), §5.3.2 (quads between a mesh point,
// its parent and its right neighbour), §3.4 and §4.3.3 (texture coordinates); Skjermo & Eidheim
// 2005 as summarised in §2.4.1 (backward connection onto a side of an appended box).
//
// Construction (docs/stages/mesh.md, "Joints", has figures in words):
//   - A ring is four vertices at angles 45°, 135°, 225°, 315° in its frame (n, b), at distance
//     corner_scale * radius from the centre, ordered counter-clockwise around the tangent t.
//   - Every ring's top face is a *port*: at ring k the segments are the branch's continuation
//     (ring k + 1) and the children growing from ring k. No segment: the port is filled (a tip
//     cap). One: the port is bridged to the segment's first ring by four quads (the tube).
//     Several: Connect(port, segments):
//       1. sort by radius, descending (ties: continuation first, then tree order);
//       2. backward: the largest lies behind the port or faces away from it -> the port is
//          extruded into a box and every segment goes to the box face (top or side) its
//          direction matches best, each handled by Connect again (at most two such levels);
//       3. equal split (two largest radii within 0.1 %): a crotch is built on the port — two
//          ports Left/Right sharing a ridge quad, plus two quads closing the port's other edges
//          (4 new vertices, 3 quads) — segments go left or right by direction (never all to one
//          side) and each side is handled by Connect;
//       4. ordinary: the port is bridged to the largest segment's first ring; the four bridge
//          quads are the box's side faces; every other segment goes to the side whose outward
//          normal best matches its direction; a side with none stays a face, with one it is
//          bridged, with more it is handled by Connect (recursion).
//   - A root's first ring is closed by a base cap unless open_base; its four edges are marked a
//     crease (QuadMesh::crease), so subdivision keeps the foot flat and full-width on the ground.
// The result is, by construction, a closed (or, with open_base, bounded only by the base rings),
// consistently oriented 2-manifold made of quads only, one connected component per root; each
// bridge uses the port's edges once in the port's direction.
//
// Texture coordinates (per face corner): u = 0, 1/4, 1/2, 3/4 around a ring's corners and 1 where
// the last quad meets corner 0 (the seam), v = the ring's v (mesh_skeleton.h); both times
// `bark_repeat`. A bridge to a child takes the child ring's u at both ends (the port end gets
// the u of the corner it is joined to and the v of the ring the joint belongs to), so joints
// have a texture seam along the port but no stretching. Caps, crotches and backward boxes get a
// planar projection at the same texel density.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "stages/mesh/mesh_skeleton.h"
#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh {

struct JointStats {
  std::size_t bridges = 0;             // "connect directly": port -> ring, 4 quads
  std::size_t ordinary_joints = 0;     // Connect with an ordinary box
  std::size_t split_joints = 0;        // Connect with the equal-split crotch
  std::size_t recursive_sides = 0;     // box sides that took more than one segment
  std::size_t backward_fallbacks = 0;  // ports extruded because the largest segment lay behind
  std::size_t insets = 0;              // ports inset before bridging to a much smaller ring
  std::size_t tip_caps = 0;
  std::size_t base_caps = 0;
  std::size_t components = 0;  // roots (one closed mesh each)
};

struct BarkOptions {
  bool open_base = false;     // leave the first ring of every root open
  double corner_scale = 1.0;  // ring corner distance / radius (see corner_scale_for_subdivision)
  int bark_repeat = 1;        // texture repeats around a ring (and along it, to stay square)
};

// The ring corner distance (in radii) that gives a straight branch subdivided `levels` times by
// Catmull–Clark the cross-section area of a circle of its radius (levels 0..3; each level
// shrinks the square section towards its B-spline limit curve).
double corner_scale_for_subdivision(int levels);

// Builds the bark mesh of every branch of `skeleton`. `stats` may be null.
// Vertices: 4 per ring + 4 per equal-split crotch + 4 per backward box. O(rings).
// `ring_vertices` (may be null) receives, per skeleton branch and ring, the index of the ring's
// first vertex (its four corners are consecutive).
QuadMesh build_bark_mesh(const MeshSkeleton& skeleton, const BarkOptions& options, JointStats* stats,
                         std::vector<std::vector<std::uint32_t>>* ring_vertices = nullptr);

}  // namespace sylva::mesh
