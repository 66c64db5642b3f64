// Topology (OpenMesh) and self-intersection (CGAL) checks of a quad mesh (topology_check.h).
#include "stages/mesh/topology_check.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <iterator>
#include <numeric>
#include <vector>

#include "stages/mesh/openmesh_types.h"

namespace sylva::mesh {

TopologyReport check_topology(const QuadMesh& mesh) {
  TopologyReport r;
  detail::PolyMesh m;
  r.refused_faces = detail::to_openmesh(mesh, m);
  r.vertices = m.n_vertices();
  r.edges = m.n_edges();
  r.faces = m.n_faces();
  for (const auto eh : m.edges())
    if (m.is_boundary(eh)) ++r.boundary_edges;
  for (const auto vh : m.vertices())
    if (m.is_isolated(vh)) ++r.isolated_vertices;
  r.euler = static_cast<long long>(r.vertices) - static_cast<long long>(r.edges) + static_cast<long long>(r.faces);

  // Face-connected components (union-find over the quads' vertices).
  std::vector<std::uint32_t> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<char> used(mesh.positions.size(), 0);
  for (const Quad& q : mesh.quads)
    for (std::size_t i = 0; i < 4; ++i) {
      used[q[i]] = 1;
      parent[find(q[i])] = find(q[(i + 1) % 4]);
    }
  for (std::uint32_t v = 0; v < parent.size(); ++v)
    if (used[v] && find(v) == v) ++r.components;

  // Signed volume by the divergence theorem over the quads' two triangles.
  double six_v = 0;
  for (const Quad& q : mesh.quads) {
    const Vec3& a = mesh.positions[q[0]];
    for (std::size_t i = 1; i + 1 < 4; ++i) six_v += tree::dot(a, tree::cross(mesh.positions[q[i]], mesh.positions[q[i + 1]]));
  }
  r.signed_volume = six_v / 6;
  return r;
}

std::size_t count_self_intersections(const QuadMesh& mesh) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using SM = CGAL::Surface_mesh<K::Point_3>;
  SM sm;
  std::vector<SM::Vertex_index> v;
  v.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) v.push_back(sm.add_vertex(K::Point_3(p.x, p.y, p.z)));
  for (const Quad& q : mesh.quads) {
    sm.add_face(v[q[0]], v[q[1]], v[q[2]]);
    sm.add_face(v[q[0]], v[q[2]], v[q[3]]);
  }
  std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
  return pairs.size();
}

}  // namespace sylva::mesh
