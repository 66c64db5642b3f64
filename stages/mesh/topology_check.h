// Checks of the bark mesh: topology with OpenMesh, self-intersections with CGAL.
//
// The mesher guarantees a closed, consistently oriented 2-manifold by construction (box_joints.h);
// these functions verify it (the stage runs check_topology on every base mesh and fails loudly
// if it ever does not hold; tests run both on every preset).
#pragma once

#include <cstddef>

#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh {

struct TopologyReport {
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t refused_faces = 0;   // quads OpenMesh could not add: a non-manifold edge or vertex,
                                   // or an orientation that disagrees with a neighbour
                                   // (check_topology_fast: quads with a half-edge used twice or
                                   // without a matching opposite, plus non-manifold vertices)
  std::size_t boundary_edges = 0;  // edges with a single face
  std::size_t isolated_vertices = 0;
  std::size_t components = 0;  // face-connected pieces
  long long euler = 0;         // V - E + F (2 per closed genus-0 component)
  double signed_volume = 0;    // m^3; > 0 when the faces' normals point outwards

  bool manifold_and_oriented() const { return refused_faces == 0 && isolated_vertices == 0; }
  bool closed() const { return boundary_edges == 0; }
};

// Builds an OpenMesh PolyMesh from the quads and reports what it found. O(V + F).
TopologyReport check_topology(const QuadMesh& mesh);

// The same verdicts from the half-edge arrays alone (no OpenMesh; about 10x faster, so the
// stage runs it on every mesh): every directed edge used once, every edge shared by two quads
// in opposite directions (or one, on a boundary), every vertex's quads one fan. Tests check it
// agrees with check_topology.
TopologyReport check_topology_fast(const QuadMesh& mesh);

// Pairs of triangles (each quad split along its 0-2 diagonal) that intersect other than along
// a shared edge or vertex: CGAL's Polygon_mesh_processing::self_intersections on a Surface_mesh.
// A statistic: box joints of strongly bent or crowded branches can touch. O(F log F) typical.
std::size_t count_self_intersections(const QuadMesh& mesh);

}  // namespace sylva::mesh
