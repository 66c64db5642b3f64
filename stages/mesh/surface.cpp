// Quad mesh -> glTF triangles with normals and split texture seams (surface.h).
// Seed: Nystad 2010 §3.3.1 (per-vertex normal and texture coordinates).
//
// A tree at subdivision 2 has millions of quads, so the passes write the glTF arrays in place
// and keep temporaries small (every fresh megabyte costs page faults): normals per mesh vertex;
// glTF vertex ids per quad corner (stored in the index array); the vertex arrays, sized exactly;
// triangles (expanding the corner ids into triangle indices in place).
#include "stages/mesh/surface.h"

#include <array>
#include <cmath>

namespace sylva::mesh {
namespace {

using tree::cross;
using tree::dot;
using tree::length;

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

}  // namespace

gltf::Primitive to_primitive(const QuadMesh& m) {
  const std::size_t nv = m.positions.size();
  const std::size_t nf = m.quads.size();

  // 1. Smooth normals per mesh vertex: the sum of its quads' normals (cross product of the
  // diagonals: twice the quad's area times its normal).
  std::vector<Vec3> normal(nv, Vec3{});
  for (const Quad& q : m.quads) {
    const Vec3 n = cross(m.positions[q[2]] - m.positions[q[0]], m.positions[q[3]] - m.positions[q[1]]);
    for (std::uint32_t v : q) normal[v] += n;
  }

  // 2. glTF vertex ids: one per distinct (vertex, uv), in first-use order. The id of corner i
  // of quad f goes to indices[4 f + i] for now.
  gltf::Primitive p;
  p.mode = gltf::PrimitiveMode::kTriangles;
  p.indices.resize(6 * nf);
  std::vector<std::uint32_t> head(nv, kNone), next, source;
  std::vector<Uv> uv;
  const std::size_t guess = nv + nv / 4 + 64;  // seams add a few percent of the vertices
  next.reserve(guess);
  source.reserve(guess);
  uv.reserve(guess);
  for (std::size_t f = 0; f < nf; ++f)
    for (std::size_t i = 0; i < 4; ++i) {
      const std::uint32_t v = m.quads[f][i];
      const Uv& t = m.uvs[f][i];
      std::uint32_t g = head[v], last = kNone;
      while (g != kNone && !(uv[g] == t)) last = g, g = next[g];
      if (g == kNone) {
        g = static_cast<std::uint32_t>(source.size());
        (last == kNone ? head[v] : next[last]) = g;
        next.push_back(kNone);
        source.push_back(v);
        uv.push_back(t);
      }
      p.indices[4 * f + i] = g;
    }
  const std::size_t ng = source.size();
  head = {};
  next = {};

  // 3. Vertex arrays.
  p.positions.resize(3 * ng);
  p.normals.resize(3 * ng);
  p.texcoords.resize(2 * ng);
  for (std::size_t g = 0; g < ng; ++g) {
    const Vec3& x = m.positions[source[g]];
    const Vec3& ns = normal[source[g]];
    const double l = length(ns);
    const Vec3 n = l > 0 ? ns / l : Vec3{0, 1, 0};
    float* P = &p.positions[3 * g];
    float* N = &p.normals[3 * g];
    P[0] = static_cast<float>(x.x), P[1] = static_cast<float>(x.y), P[2] = static_cast<float>(x.z);
    N[0] = static_cast<float>(n.x), N[1] = static_cast<float>(n.y), N[2] = static_cast<float>(n.z);
    p.texcoords[2 * g] = uv[g].u;
    p.texcoords[2 * g + 1] = uv[g].v;
  }
  normal = {};
  source = {};
  uv = {};

  // 4. Triangles along the shorter diagonal (the corner ids expand in place, last quad first, so
  // no id is overwritten before it is read).
  for (std::size_t f = nf; f-- > 0;) {
    const Quad& q = m.quads[f];
    const std::uint32_t c[4] = {p.indices[4 * f], p.indices[4 * f + 1], p.indices[4 * f + 2],
                                p.indices[4 * f + 3]};
    std::uint32_t* idx = &p.indices[6 * f];
    const Vec3 d02 = m.positions[q[2]] - m.positions[q[0]];
    const Vec3 d13 = m.positions[q[3]] - m.positions[q[1]];
    if (dot(d13, d13) < dot(d02, d02)) {
      idx[0] = c[0], idx[1] = c[1], idx[2] = c[3], idx[3] = c[1], idx[4] = c[2], idx[5] = c[3];
    } else {
      idx[0] = c[0], idx[1] = c[1], idx[2] = c[2], idx[3] = c[0], idx[4] = c[2], idx[5] = c[3];
    }
  }
  // A triangle stored as a quad (last two corners equal, quad_mesh.h) gave one empty triangle.
  std::size_t kept = 0;
  for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3) {
    const std::uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
    if (a == b || b == c || a == c) continue;
    p.indices[kept++] = a, p.indices[kept++] = b, p.indices[kept++] = c;
  }
  p.indices.resize(kept);
  return p;
}

}  // namespace sylva::mesh
