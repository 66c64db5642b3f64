// Catmull–Clark subdivision of the bark mesh, with texture coordinates as Nystad prescribes.
//
// Seeds: Catmull & Clark 1978 (as restated in Nystad 2010 §2.1.1, eq. 2.1: face point = centroid;
// edge point = mean of the edge's ends and the two adjacent face points, on a boundary its
// midpoint; vertex point = (F + 2R + (n - 3) P) / n); Nystad 2010 §3.4.3 (texture space
// degeneration: u is *not* moved at existing vertices; a new edge point takes the plain average
// of the edge's two u — we apply the same linear rule to v, and the face point takes the average
// of the face's corners, so uvs are refined per face and seams stay where they were).
// Boundary vertices (open_base) use the cubic B-spline curve rule 3/4 P + 1/8 (P_prev + P_next).
// Creases (QuadMesh::crease; Hoppe et al. 1994, OpenSubdiv's infinitely sharp edges): an edge
// between two crease vertices is subdivided like a boundary (midpoint; curve rule at a vertex
// with two crease edges), so a capped trunk base stays a flat B-spline curve on the ground.
//
// Two implementations produce the same geometry:
//   - kNative: array based; the refinement (edges, opposite half-edges) is computed once per
//     level and applied to positions and uvs. Vertex order: old vertices, then one per edge,
//     then one per face; quad 4 f + i is the child of quad f at its corner i. This is the
//     stage's default: about 10x faster than OpenMesh's on tree meshes (docs/stages/mesh.md).
//   - kOpenMesh: OpenMesh's CatmullClarkT on a PolyMesh, uvs carried over by the same rule.
//     Its boundary rule differs ((P + both boundary edge midpoints) / 3) and it knows no
//     creases, so the two agree on closed meshes without creases only (the tests compare them
//     there); it is kept as the reference.
#pragma once

#include <cstdint>
#include <vector>

#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh {

enum class Subdivider { kNative, kOpenMesh };

// `levels` Catmull–Clark steps (0 returns the input). Every quad becomes 4 per level; the
// input must be a quad mesh whose edges have at most two faces (the bark mesh is). Throws
// std::invalid_argument for a mesh OpenMesh rejects (kOpenMesh only).
QuadMesh subdivide(const QuadMesh& mesh, int levels, Subdivider subdivider = Subdivider::kNative);

// One Catmull–Clark step on the quads with smooth[f] != 0 only (native rules, creases as above):
// a smooth quad becomes its four children; every other quad keeps its corners, and a vertex it
// shares with a smooth quad takes its Catmull–Clark vertex point, so the two regions meet without
// cracks. The edge points of the edges a flat quad shares with smooth ones are inserted into it,
// and the resulting polygon (4 + k corners, k split edges) is fanned into quads from its first
// inserted point, the last piece a triangle when k is odd — stored as a quad whose last two
// corners are equal (quad_mesh.h). uvs follow the same per-face rule. Vertex order: the old
// vertices, the points of split edges, the face points of smooth quads.
QuadMesh subdivide_selected(const QuadMesh& mesh, const std::vector<std::uint8_t>& smooth);

}  // namespace sylva::mesh
