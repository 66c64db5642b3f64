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

#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh {

enum class Subdivider { kNative, kOpenMesh };

// `levels` Catmull–Clark steps (0 returns the input). Every quad becomes 4 per level; the
// input must be a quad mesh whose edges have at most two faces (the bark mesh is). Throws
// std::invalid_argument for a mesh OpenMesh rejects (kOpenMesh only).
QuadMesh subdivide(const QuadMesh& mesh, int levels, Subdivider subdivider = Subdivider::kNative);

}  // namespace sylva::mesh
