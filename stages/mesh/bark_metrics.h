// How closely the bark mesh follows the skeleton: the trunk's diameter at a height, the enclosed
// volume, the lowest point — against the skeleton's radii and its Σ π r² l. Pure; used by the
// tests (generated and imported trees) and the mesh report.
//
// Definitions:
//   cross-section diameter at height h: the plane y = h cuts the mesh's triangles into segments,
//     oriented by the triangles' outward normals; the segments within `reach` (xz distance) of
//     the trunk's axis at h bound the trunk's section, whose area A is half the sum of their
//     cross products (a closed loop needs no ordering); the diameter is 2 sqrt(A / pi), the
//     diameter of the circle of that area;
//   skeleton diameter at h: 2 x the trunk's (branch 0's) radius interpolated where its axis
//     reaches h;
//   mesh volume: the divergence theorem over the closed mesh's triangles;
//   skeleton volume: Σ over the meshed branches' segments of the frustum volume
//     π l (r0² + r0 r1 + r1²) / 3 (Σ π r² l for a QSM's constant-radius cylinders); joint
//     segments (attachment point to a child's first node) are not counted.
#pragma once

#include <vector>

#include "libs/tree/tree.h"
#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh {

// Area-equivalent diameter of the trunk's section at height h (m), 0 when the plane misses it.
double trunk_section_diameter(const QuadMesh& mesh, const tree::Tree& tree, double h);

// 2 x branch 0's radius where its axis reaches height h (m); 0 if it never does.
double skeleton_diameter(const tree::Tree& tree, double h);

// The height (m, above the trunk's base) at which to measure the breast-height diameter: `nominal`
// (1.3 m) unless a child of the trunk attaches there, else the nearest height below (then above),
// in 1 cm steps within 0.5 m, clear of every child's joint — the forester's rule for a branch or
// swelling at breast height (measure just below it, where the stem form is normal). A child's
// joint spans its attachment height +/- 1.5 x its first radius.
// Returns a negative value when no such height exists or the trunk is thinner than `min_diameter`
// there (a shrub's stem: breast height is not defined).
// Children with omit[i] != 0 (not meshed; omit may be empty) have no joint.
double breast_height(const tree::Tree& tree, const std::vector<char>& omit = {}, double nominal = 1.3,
                     double min_diameter = 0.05);

// Enclosed volume of a closed quad mesh (m^3).
double mesh_volume(const QuadMesh& mesh);

// Σ of frustum volumes over the branches with omit[i] == 0 (omit may be empty) (m^3). With
// `outside_parents`, every child's polyline starts at its attachment point (the implicit joint
// segment, at the child's first radius: a generated child's first node lies (1 + S) r outside
// the parent's axis, and the bark fills that gap) and the part within the parent's radius of the
// attachment point is left out (a QSM starts its children on the parent's axis, so the plain sum
// counts that volume twice, once in the parent, although no bark can enclose it twice).
// Radii below `min_radius` count at it (the mesh stage's min_radius_m: the bark cannot be thinner).
double skeleton_volume(const tree::Tree& tree, const std::vector<char>& omit = {},
                       bool outside_parents = false, double min_radius = 0);

// Lowest y of any mesh vertex (m).
double lowest_point(const QuadMesh& mesh);

}  // namespace sylva::mesh
