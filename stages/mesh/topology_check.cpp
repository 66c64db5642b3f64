// Topology (OpenMesh) and self-intersection (CGAL) checks of a quad mesh (topology_check.h).
#include "stages/mesh/topology_check.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <iterator>
#include <numeric>
#include <vector>

#include "stages/mesh/halfedges.h"
#include "stages/mesh/openmesh_types.h"

namespace sylva::mesh {
namespace {

// Components, Euler characteristic and signed volume: the parts both checks share.
void finish(const QuadMesh& mesh, TopologyReport& r) {
  r.euler =
      static_cast<long long>(r.vertices) - static_cast<long long>(r.edges) + static_cast<long long>(r.faces);
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
  r.components = 0;
  r.isolated_vertices = 0;
  for (std::uint32_t v = 0; v < parent.size(); ++v) {
    if (used[v] && find(v) == v) ++r.components;
    if (!used[v]) ++r.isolated_vertices;
  }
  // Signed volume by the divergence theorem over the quads' two triangles.
  double six_v = 0;
  for (const Quad& q : mesh.quads) {
    const Vec3& a = mesh.positions[q[0]];
    for (std::size_t i = 1; i + 1 < 4; ++i)
      six_v += tree::dot(a, tree::cross(mesh.positions[q[i]], mesh.positions[q[i + 1]]));
  }
  r.signed_volume = six_v / 6;
}

}  // namespace

TopologyReport check_topology_fast(const QuadMesh& mesh) {
  TopologyReport r;
  const std::vector<std::uint32_t> opp = detail::opposite_halfedges(mesh);
  const std::size_t nh = opp.size();
  const std::size_t nv = mesh.positions.size();
  auto from = [&](std::size_t h) { return mesh.quads[h / 4][h % 4]; };
  auto prev = [](std::uint32_t h) { return (h & ~3u) | ((h + 3) & 3u); };
  auto next = [](std::uint32_t h) { return (h & ~3u) | ((h + 1) & 3u); };
  std::vector<char> bad_face(mesh.quads.size(), 0);
  std::vector<std::uint32_t> valence(nv, 0), any_out(nv, detail::kNoHalfedge);
  std::size_t boundary = 0;
  for (std::uint32_t h = 0; h < nh; ++h) {
    ++valence[from(h)];
    any_out[from(h)] = h;
    if (opp[h] == detail::kNoHalfedge) {
      ++boundary;
    } else if (opp[opp[h]] != h) {
      bad_face[h / 4] = 1;  // a third quad on this edge, or a half-edge used twice
    }
  }
  // Each vertex's quads must form one fan: walking around it from any outgoing half-edge (both
  // ways, on a boundary) must meet every outgoing half-edge.
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (valence[v] == 0) continue;
    const std::uint32_t start = any_out[v];
    std::uint32_t seen = 1;
    bool open = false;
    for (std::uint32_t h = start;;) {
      const std::uint32_t in = opp[prev(h)];
      if (in == detail::kNoHalfedge) {
        open = true;
        break;
      }
      h = in;
      if (h == start || seen > valence[v]) break;
      ++seen;
    }
    if (open)
      for (std::uint32_t h = start;;) {
        if (opp[h] == detail::kNoHalfedge) break;
        h = next(opp[h]);
        if (h == start || seen > valence[v]) break;
        ++seen;
      }
    if (seen != valence[v]) bad_face[any_out[v] / 4] = 1;
  }
  for (char b : bad_face) r.refused_faces += b != 0;
  r.vertices = nv;
  r.faces = mesh.quads.size();
  r.boundary_edges = boundary;
  r.edges = (nh + boundary) / 2;
  finish(mesh, r);
  return r;
}

TopologyReport check_topology(const QuadMesh& mesh) {
  TopologyReport r;
  detail::PolyMesh m;
  r.refused_faces = detail::to_openmesh(mesh, m);
  r.vertices = m.n_vertices();
  r.edges = m.n_edges();
  r.faces = m.n_faces();
  for (const auto eh : m.edges())
    if (m.is_boundary(eh)) ++r.boundary_edges;
  finish(mesh, r);
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
