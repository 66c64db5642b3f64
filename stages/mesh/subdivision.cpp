// Catmull–Clark (Catmull & Clark 1978; Nystad 2010 §2.1.1 eq. 2.1) with Nystad's texture rule
// (§3.4.3). OpenSubdiv's layering in miniature: refine the topology once per level (half-edge
// opposites, edge numbering), then apply it to positions and to face-varying uvs.
#include "stages/mesh/subdivision.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <stdexcept>

// OpenMesh's subdivider header needs the mesh types declared first.
#include "stages/mesh/halfedges.h"
#include "stages/mesh/openmesh_types.h"
// clang-format off
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
// clang-format on

namespace sylva::mesh {

namespace detail {

std::size_t to_openmesh(const QuadMesh& in, PolyMesh& out) {
  out.clear();
  out.reserve(in.positions.size(), in.quads.size() * 2, in.quads.size());
  for (const Vec3& p : in.positions) out.add_vertex(PolyMesh::Point(p.x, p.y, p.z));
  std::size_t refused = 0;
  const bool err_enabled = omerr().is_enabled();
  omerr().disable();  // OpenMesh prints "complex edge" per refused face; we count them instead
  for (const Quad& q : in.quads) {
    std::vector<PolyMesh::VertexHandle> vs = {
        PolyMesh::VertexHandle(static_cast<int>(q[0])), PolyMesh::VertexHandle(static_cast<int>(q[1])),
        PolyMesh::VertexHandle(static_cast<int>(q[2])), PolyMesh::VertexHandle(static_cast<int>(q[3]))};
    if (q[2] == q[3]) vs.pop_back();  // a triangle (quad_mesh.h)
    if (!out.add_face(vs).is_valid()) ++refused;
  }
  if (err_enabled) omerr().enable();
  return refused;
}

}  // namespace detail

namespace {

// Runs body(i) for i in [0, n) on the TBB pool. Every body writes only its own elements, so the
// result does not depend on the thread count or the schedule.
template <typename Body>
void parallel_for(std::size_t n, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
                    });
}

Uv mid(Uv a, Uv b) { return {(a.u + b.u) * 0.5f, (a.v + b.v) * 0.5f}; }
Uv centre(const std::array<Uv, 4>& u) {
  return {(u[0].u + u[1].u + u[2].u + u[3].u) * 0.25f, (u[0].v + u[1].v + u[2].v + u[3].v) * 0.25f};
}

}  // namespace

namespace detail {

std::vector<std::uint32_t> opposite_halfedges(const QuadMesh& in) {
  const std::size_t nv = in.positions.size();
  const std::size_t nh = 4 * in.quads.size();
  auto from = [&](std::size_t h) { return in.quads[h / 4][h % 4]; };
  auto to = [&](std::size_t h) { return in.quads[h / 4][(h + 1) % 4]; };
  // Outgoing half-edges per vertex (CSR), then for a -> b the half-edge b -> a among b's.
  std::vector<std::uint32_t> first(nv + 1, 0), out(nh);
  for (std::size_t h = 0; h < nh; ++h) ++first[from(h) + 1];
  for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t h = 0; h < nh; ++h) out[fill[from(h)]++] = static_cast<std::uint32_t>(h);
  }
  std::vector<std::uint32_t> opp(nh, kNoHalfedge);
  for (std::size_t h = 0; h < nh; ++h) {
    const std::uint32_t a = from(h), b = to(h);
    for (std::uint32_t k = first[b]; k < first[b + 1]; ++k)
      if (to(out[k]) == a) {
        opp[h] = out[k];
        break;
      }
  }
  return opp;
}

}  // namespace detail

namespace {

// Half-edge h of quad h / 4 runs from corner h % 4 to the next corner.
std::uint32_t from(const QuadMesh& in, std::size_t h) { return in.quads[h / 4][h % 4]; }
std::uint32_t to(const QuadMesh& in, std::size_t h) { return in.quads[h / 4][(h + 1) % 4]; }

// Creases (Hoppe et al. 1994's sharp edges, as OpenSubdiv's infinitely sharp crease): an edge
// between two crease vertices is subdivided as a boundary — edge point at its midpoint, a crease
// vertex with two crease edges by the cubic B-spline curve rule.
bool creased(const QuadMesh& in) { return in.crease.size() == in.positions.size(); }
bool is_crease(const QuadMesh& in, std::size_t h) {
  return creased(in) && in.crease[from(in, h)] && in.crease[to(in, h)];
}

// Edge numbering: an edge takes the number of its first half-edge in (face, corner) order.
struct Edges {
  std::vector<std::uint32_t> of_half;  // half-edge -> edge
  std::vector<std::uint32_t> half;     // edge -> a half-edge of it
};

Edges number_edges(std::size_t nh, const std::vector<std::uint32_t>& opp) {
  Edges edges;
  edges.of_half.resize(nh);
  edges.half.reserve(nh / 2 + 16);
  for (std::size_t h = 0; h < nh; ++h) {
    if (opp[h] == detail::kNoHalfedge || opp[h] > h) {
      edges.of_half[h] = static_cast<std::uint32_t>(edges.half.size());
      edges.half.push_back(static_cast<std::uint32_t>(h));
    } else {
      edges.of_half[h] = edges.of_half[opp[h]];
    }
  }
  return edges;
}

// Face points (the quad's centroid) into fp, then edge points into ep.
void face_and_edge_points(const QuadMesh& in, const std::vector<std::uint32_t>& opp, const Edges& edges,
                          Vec3* fp, Vec3* ep) {
  constexpr std::uint32_t kNone = detail::kNoHalfedge;
  const auto& P = in.positions;
  parallel_for(in.quads.size(), [&](std::size_t f) {
    const Quad& q = in.quads[f];
    fp[f] = (P[q[0]] + P[q[1]] + P[q[2]] + P[q[3]]) * 0.25;
  });
  parallel_for(edges.half.size(), [&](std::size_t e) {
    const std::uint32_t h = edges.half[e];
    const Vec3 s = P[from(in, h)] + P[to(in, h)];
    ep[e] = opp[h] == kNone || is_crease(in, h) ? s * 0.5 : (s + fp[h / 4] + fp[opp[h] / 4]) * 0.25;
  });
}

// What the vertex rule needs of each vertex's one-ring.
struct VertexRings {
  std::vector<Vec3> fsum, nsum;  // sums of the adjacent face points and of the neighbours
  std::vector<std::uint32_t> valence;
  std::vector<std::uint32_t> bnd_next, bnd_prev;  // neighbours along the boundary
  std::vector<std::uint8_t> bnd_count;            // boundary half-edges touching the vertex
  // Crease neighbours of a crease vertex (its outgoing crease half-edges lead to both of them).
  std::vector<std::array<std::uint32_t, 2>> crease_nb;
  std::vector<std::uint8_t> crease_count;
};

// Every outgoing half-edge of a vertex belongs to one of its quads and leads to one of its
// neighbours, so one pass over the half-edges sums both (in half-edge order). A half-edge without
// opposite runs along the boundary.
VertexRings vertex_rings(const QuadMesh& in, const std::vector<std::uint32_t>& opp, const Vec3* fp) {
  constexpr std::uint32_t kNone = detail::kNoHalfedge;
  const std::size_t nv = in.positions.size();
  const std::size_t nh = 4 * in.quads.size();
  const bool has_creases = creased(in);
  VertexRings r;
  r.fsum.assign(nv, Vec3{});
  r.nsum.assign(nv, Vec3{});
  r.valence.assign(nv, 0);
  r.bnd_next.assign(nv, kNone);
  r.bnd_prev.assign(nv, kNone);
  r.bnd_count.assign(nv, 0);
  r.crease_nb.assign(has_creases ? nv : 0, {kNone, kNone});
  r.crease_count.assign(has_creases ? nv : 0, 0);
  for (std::size_t h = 0; h < nh; ++h) {
    const std::uint32_t a = from(in, h), b = to(in, h);
    r.fsum[a] += fp[h / 4];
    r.nsum[a] += in.positions[b];
    ++r.valence[a];
    if (opp[h] == kNone) {
      r.bnd_next[a] = b;
      r.bnd_prev[b] = a;
      ++r.bnd_count[a];
      ++r.bnd_count[b];
    }
    if (is_crease(in, h) && r.crease_nb[a][0] != b && r.crease_nb[a][1] != b) {
      if (r.crease_count[a] < 2) r.crease_nb[a][r.crease_count[a]] = b;
      ++r.crease_count[a];
    }
  }
  return r;
}

// Vertex points into vp: the crease curve rule, Catmull–Clark's interior rule, the boundary
// curve rule, or the vertex kept.
void vertex_points(const QuadMesh& in, const VertexRings& r, Vec3* vp) {
  constexpr std::uint32_t kNone = detail::kNoHalfedge;
  const auto& P = in.positions;
  const bool has_creases = creased(in);
  parallel_for(in.positions.size(), [&](std::size_t v) {
    const std::uint32_t n = r.valence[v];
    if (has_creases && in.crease[v] && r.crease_count[v] == 2 && r.bnd_count[v] == 0) {
      vp[v] = P[v] * 0.75 + (P[r.crease_nb[v][0]] + P[r.crease_nb[v][1]]) * 0.125;
    } else if (has_creases && in.crease[v] && r.crease_count[v] > 2) {
      vp[v] = P[v];  // a corner of several creases
    } else if (r.bnd_count[v] == 0 && n > 0) {
      // (F + 2R + (n - 3) P) / n with R = (P + mean neighbour) / 2.
      const double dn = n;
      vp[v] = r.fsum[v] / (dn * dn) + r.nsum[v] / (dn * dn) + P[v] * ((dn - 2) / dn);
    } else if (r.bnd_count[v] == 2 && r.bnd_next[v] != kNone && r.bnd_prev[v] != kNone) {
      vp[v] = P[v] * 0.75 + (P[r.bnd_next[v]] + P[r.bnd_prev[v]]) * 0.125;
    } else {
      vp[v] = P[v];  // isolated, or a corner where the boundary is not a simple curve
    }
  });
}

// Crease flags of the next level: old crease vertices and the edge points of crease edges.
void next_creases(const QuadMesh& in, const Edges& edges, QuadMesh& outm) {
  const std::size_t nv = in.positions.size(), ne = edges.half.size();
  outm.crease.assign(nv + ne + in.quads.size(), 0);
  for (std::size_t v = 0; v < nv; ++v) outm.crease[v] = in.crease[v];
  for (std::size_t e = 0; e < ne; ++e) outm.crease[nv + e] = is_crease(in, edges.half[e]) ? 1 : 0;
}

// The four children of every quad, with Nystad's uvs (corner, edge midpoints, centre) and the
// parent's kind.
void child_quads(const QuadMesh& in, const Edges& edges, QuadMesh& outm) {
  const std::size_t nv = in.positions.size(), ne = edges.half.size(), nf = in.quads.size();
  outm.quads.resize(4 * nf);
  outm.uvs.resize(4 * nf);
  outm.kinds.resize(in.kinds.size() == nf ? 4 * nf : 0);
  const std::uint32_t ebase = static_cast<std::uint32_t>(nv), fbase = static_cast<std::uint32_t>(nv + ne);
  const std::vector<std::uint32_t>& edge = edges.of_half;
  parallel_for(nf, [&](std::size_t f) {
    const Quad& q = in.quads[f];
    const auto& uv = in.uvs[f];
    const Uv c = centre(uv);
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t prev = (i + 3) % 4;
      outm.quads[4 * f + i] = {q[i], ebase + edge[4 * f + i], fbase + static_cast<std::uint32_t>(f),
                               ebase + edge[4 * f + prev]};
      outm.uvs[4 * f + i] = {uv[i], mid(uv[i], uv[(i + 1) % 4]), c, mid(uv[prev], uv[i])};
      if (!outm.kinds.empty()) outm.kinds[4 * f + i] = in.kinds[f];
    }
  });
}

// Opposites of the children's half-edges. Child c = 4 f + i has corners (q_i, E_i, F, E_i-1):
// half-edges 1 and 2 are inside f and pair with the neighbouring children; 0 and 3 are halves
// of f's edges and pair with the children of the face across.
std::vector<std::uint32_t> child_opposites(std::size_t nf, const std::vector<std::uint32_t>& opp) {
  constexpr std::uint32_t kNone = detail::kNoHalfedge;
  std::vector<std::uint32_t> child_opp(4 * 4 * nf);
  parallel_for(nf, [&](std::size_t f) {
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t base = 4 * (4 * f + i);
      child_opp[base + 1] = static_cast<std::uint32_t>(4 * (4 * f + (i + 1) % 4) + 2);
      child_opp[base + 2] = static_cast<std::uint32_t>(4 * (4 * f + (i + 3) % 4) + 1);
      const std::uint32_t o = opp[4 * f + i];  // q_i -> q_i+1, seen from across
      child_opp[base + 0] =
          o == kNone ? kNone : static_cast<std::uint32_t>(4 * (4 * (o / 4) + (o % 4 + 1) % 4) + 3);
      const std::uint32_t op = opp[4 * f + (i + 3) % 4];  // q_i-1 -> q_i, seen from across
      child_opp[base + 3] = op == kNone ? kNone : static_cast<std::uint32_t>(4 * (4 * (op / 4) + op % 4) + 0);
    }
  });
  return child_opp;
}

// One native Catmull–Clark step. `opp` holds the input's opposite half-edges and is replaced by
// the output's, derived from the refinement itself (no search), so the next level is cheaper.
QuadMesh step(const QuadMesh& in, std::vector<std::uint32_t>& opp, bool last) {
  const std::size_t nv = in.positions.size();
  const std::size_t nf = in.quads.size();

  // 1. Topology: edge numbering.
  const Edges edges = number_edges(4 * nf, opp);
  const std::size_t ne = edges.half.size();

  // 2. Points: old vertices, then one per edge, then one per face.
  QuadMesh outm;
  outm.positions.resize(nv + ne + nf);
  Vec3* vp = outm.positions.data();
  Vec3* ep = vp + nv;
  Vec3* fp = ep + ne;
  face_and_edge_points(in, opp, edges, fp, ep);
  vertex_points(in, vertex_rings(in, opp, fp), vp);

  // 3. Face-varying data and topology of the next level.
  if (creased(in)) next_creases(in, edges, outm);
  child_quads(in, edges, outm);
  if (last) return outm;  // no further level needs the opposites
  opp = child_opposites(nf, opp);
  return outm;
}

// OpenMesh's CatmullClarkT, one level; uvs follow from the vertex numbering it produces
// (old vertices, then one per edge in edge order, then one per face in face order).
QuadMesh step_openmesh(const QuadMesh& in) {
  detail::PolyMesh m;
  if (detail::to_openmesh(in, m) != 0)
    throw std::invalid_argument(
        "OpenMesh refused a quad: the mesh is not a consistently oriented 2-manifold");
  const std::size_t nv = m.n_vertices(), ne = m.n_edges(), nf = m.n_faces();
  std::vector<std::array<std::uint32_t, 2>> ends(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    const auto h = m.halfedge_handle(m.edge_handle(static_cast<int>(e)), 0);
    ends[e] = {static_cast<std::uint32_t>(m.from_vertex_handle(h).idx()),
               static_cast<std::uint32_t>(m.to_vertex_handle(h).idx())};
  }
  OpenMesh::Subdivider::Uniform::CatmullClarkT<detail::PolyMesh> cc;
  cc.attach(m);
  cc(1);
  cc.detach();
  if (m.n_vertices() != nv + ne + nf)
    throw std::logic_error("OpenMesh Catmull-Clark: unexpected vertex numbering");
  auto uv_in = [&](std::size_t f, std::uint32_t v) {
    for (std::size_t i = 0; i < 4; ++i)
      if (in.quads[f][i] == v) return in.uvs[f][i];
    throw std::logic_error("OpenMesh Catmull-Clark: corner not in its parent face");
  };
  QuadMesh out;
  out.positions.reserve(m.n_vertices());
  for (const auto vh : m.vertices()) {
    const auto& p = m.point(vh);
    out.positions.push_back({p[0], p[1], p[2]});
  }
  out.quads.reserve(m.n_faces());
  out.uvs.reserve(m.n_faces());
  for (const auto fh : m.faces()) {
    Quad q{};
    std::size_t i = 0, parent = 0;
    for (const auto vh : m.fv_range(fh)) {
      if (i < 4) q[i] = static_cast<std::uint32_t>(vh.idx());
      ++i;
    }
    if (i != 4) throw std::logic_error("OpenMesh Catmull-Clark produced a face that is not a quad");
    for (std::uint32_t v : q)
      if (v >= nv + ne) parent = v - nv - ne;
    std::array<Uv, 4> uv;
    for (std::size_t c = 0; c < 4; ++c) {
      const std::uint32_t v = q[c];
      if (v < nv) {
        uv[c] = uv_in(parent, v);
      } else if (v < nv + ne) {
        uv[c] = mid(uv_in(parent, ends[v - nv][0]), uv_in(parent, ends[v - nv][1]));
      } else {
        uv[c] = centre(in.uvs[parent]);
      }
    }
    out.quads.push_back(q);
    out.uvs.push_back(uv);
    if (in.kinds.size() == in.quads.size()) out.kinds.push_back(in.kinds[parent]);
  }
  return out;
}

}  // namespace

QuadMesh subdivide_selected(const QuadMesh& in, const std::vector<std::uint8_t>& smooth) {
  const std::size_t nv = in.positions.size(), nf = in.quads.size();
  if (smooth.size() != nf) throw std::invalid_argument("subdivide_selected: one flag per quad needed");
  std::vector<std::uint32_t> opp = detail::opposite_halfedges(in);
  // The full step gives every vertex, edge and face point (vertex points from the whole
  // neighbourhood); the selection then keeps the ones the smooth quads use.
  const QuadMesh full = step(in, opp, true);
  const std::size_t ne = full.positions.size() - nv - nf;
  constexpr std::uint32_t kNone = detail::kNoHalfedge;
  auto edge_of = [&](std::size_t f, std::size_t i) {
    return full.quads[4 * f + i][1] - static_cast<std::uint32_t>(nv);
  };
  std::vector<std::uint8_t> touched(nv, 0), split(ne, 0);
  for (std::size_t f = 0; f < nf; ++f)
    if (smooth[f])
      for (std::size_t i = 0; i < 4; ++i) {
        touched[in.quads[f][i]] = 1;
        split[edge_of(f, i)] = 1;
      }
  QuadMesh out;
  std::vector<std::uint32_t> id(full.positions.size(), kNone);
  out.positions.reserve(full.positions.size());
  for (std::size_t v = 0; v < nv; ++v) {
    id[v] = static_cast<std::uint32_t>(v);
    out.positions.push_back(touched[v] ? full.positions[v] : in.positions[v]);
  }
  for (std::size_t e = 0; e < ne; ++e)
    if (split[e]) {
      id[nv + e] = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(full.positions[nv + e]);
    }
  for (std::size_t f = 0; f < nf; ++f)
    if (smooth[f]) {
      id[nv + ne + f] = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(full.positions[nv + ne + f]);
    }
  if (full.crease.size() == full.positions.size()) {
    out.crease.assign(out.positions.size(), 0);
    for (std::size_t v = 0; v < full.positions.size(); ++v)
      if (id[v] != kNone) out.crease[id[v]] = full.crease[v];
  }
  const bool kinds = in.kinds.size() == nf;
  for (std::size_t f = 0; f < nf; ++f) {
    if (smooth[f]) {
      for (std::size_t c = 4 * f; c < 4 * f + 4; ++c) {
        const Quad& q = full.quads[c];
        out.quads.push_back({id[q[0]], id[q[1]], id[q[2]], id[q[3]]});
        out.uvs.push_back(full.uvs[c]);
        if (kinds) out.kinds.push_back(in.kinds[f]);
      }
      continue;
    }
    // The flat quad's polygon: its corners with the split edges' points between them.
    std::array<std::uint32_t, 8> pv{};
    std::array<Uv, 8> pu{};
    std::size_t n = 0, first_inserted = 0;
    bool any = false;
    for (std::size_t i = 0; i < 4; ++i) {
      pv[n] = in.quads[f][i];
      pu[n++] = in.uvs[f][i];
      const std::uint32_t e = edge_of(f, i);
      if (split[e]) {
        if (!any) first_inserted = n;
        any = true;
        pv[n] = id[nv + e];
        pu[n++] = mid(in.uvs[f][i], in.uvs[f][(i + 1) % 4]);
      }
    }
    auto emit = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t d) {
      out.quads.push_back({pv[a % n], pv[b % n], pv[c % n], pv[d % n]});
      out.uvs.push_back({pu[a % n], pu[b % n], pu[c % n], pu[d % n]});
      if (kinds) out.kinds.push_back(in.kinds[f]);
    };
    const std::size_t s = first_inserted;
    std::size_t k = 1;
    for (; k + 2 < n; k += 2) emit(s, s + k, s + k + 1, s + k + 2);
    if (k + 1 < n) emit(s, s + k, s + k + 1, s + k + 1);  // the triangle of an odd polygon
  }
  return out;
}

QuadMesh subdivide(const QuadMesh& mesh, int levels, Subdivider subdivider) {
  QuadMesh m = mesh;
  if (levels <= 0) return m;
  if (subdivider == Subdivider::kOpenMesh) {
    for (int l = 0; l < levels; ++l) m = step_openmesh(m);
    return m;
  }
  std::vector<std::uint32_t> opp = detail::opposite_halfedges(m);
  for (int l = 0; l < levels; ++l) m = step(m, opp, l + 1 == levels);
  return m;
}

}  // namespace sylva::mesh
