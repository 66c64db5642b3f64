// Quad mesh -> glTF triangles with normals, tangents and split texture seams (surface.h).
// Seed: Nystad 2010 §3.3.1 (per-vertex normal, tangent and texture coordinates).
#include "stages/mesh/surface.h"

#include <cmath>

namespace sylva::mesh {
namespace {

using tree::cross;
using tree::dot;
using tree::length;
using tree::normalized;

// Any unit vector orthogonal to unit n.
Vec3 orthogonal(Vec3 n) {
  const Vec3 a = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return normalized(cross(n, a));
}

}  // namespace

gltf::Primitive to_primitive(const QuadMesh& m) {
  const std::size_t nv = m.positions.size();
  const std::size_t nf = m.quads.size();

  // 1. Smooth normals per topological vertex.
  std::vector<Vec3> normal(nv, Vec3{});
  for (const Quad& q : m.quads) {
    const Vec3 n = cross(m.positions[q[2]] - m.positions[q[0]], m.positions[q[3]] - m.positions[q[1]]);
    for (std::uint32_t v : q) normal[v] += n;
  }
  for (Vec3& n : normal) {
    n = normalized(n);
    if (length(n) == 0) n = Vec3{0, 1, 0};
  }

  // 2. glTF vertices: one per distinct (vertex, uv), in first-use order.
  std::vector<std::uint32_t> head(nv, 0xFFFFFFFFu);  // first glTF vertex of each mesh vertex
  std::vector<std::uint32_t> next;                   // chain of glTF vertices of the same vertex
  std::vector<std::uint32_t> source;                 // glTF vertex -> mesh vertex
  std::vector<Uv> uv;
  std::vector<std::array<std::uint32_t, 4>> corner(nf);
  next.reserve(nv + nv / 4);
  source.reserve(nv + nv / 4);
  uv.reserve(nv + nv / 4);
  for (std::size_t f = 0; f < nf; ++f) {
    for (std::size_t i = 0; i < 4; ++i) {
      const std::uint32_t v = m.quads[f][i];
      const Uv& t = m.uvs[f][i];
      std::uint32_t g = head[v];
      std::uint32_t last = 0xFFFFFFFFu;
      while (g != 0xFFFFFFFFu && !(uv[g] == t)) last = g, g = next[g];
      if (g == 0xFFFFFFFFu) {
        g = static_cast<std::uint32_t>(source.size());
        source.push_back(v);
        uv.push_back(t);
        next.push_back(0xFFFFFFFFu);
        if (last == 0xFFFFFFFFu) {
          head[v] = g;
        } else {
          next[last] = g;
        }
      }
      corner[f][i] = g;
    }
  }
  const std::size_t ng = source.size();

  // 3. Tangents from the uv gradient of each quad's two triangles, per glTF vertex.
  std::vector<Vec3> tan(ng, Vec3{}), bit(ng, Vec3{});
  auto accumulate = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Vec3 e1 = m.positions[source[b]] - m.positions[source[a]];
    const Vec3 e2 = m.positions[source[c]] - m.positions[source[a]];
    const double du1 = uv[b].u - uv[a].u, dv1 = uv[b].v - uv[a].v;
    const double du2 = uv[c].u - uv[a].u, dv2 = uv[c].v - uv[a].v;
    const double det = du1 * dv2 - du2 * dv1;
    if (det == 0 || !std::isfinite(det)) return;
    const double r = 1.0 / det;
    const Vec3 t = (e1 * dv2 - e2 * dv1) * r;
    const Vec3 s = (e2 * du1 - e1 * du2) * r;
    // Weight by the triangle's area so tiny triangles (tips) do not dominate.
    const double w = length(cross(e1, e2)) * std::abs(det);
    for (std::uint32_t g : {a, b, c}) {
      tan[g] += t * w;
      bit[g] += s * w;
    }
  };

  // 4. Triangles along the shorter diagonal.
  gltf::Primitive p;
  p.mode = gltf::PrimitiveMode::kTriangles;
  p.indices.reserve(6 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& c = corner[f];
    const Quad& q = m.quads[f];
    const double d02 = length(m.positions[q[2]] - m.positions[q[0]]);
    const double d13 = length(m.positions[q[3]] - m.positions[q[1]]);
    if (d13 < d02) {
      p.indices.insert(p.indices.end(), {c[0], c[1], c[3], c[1], c[2], c[3]});
      accumulate(c[0], c[1], c[3]);
      accumulate(c[1], c[2], c[3]);
    } else {
      p.indices.insert(p.indices.end(), {c[0], c[1], c[2], c[0], c[2], c[3]});
      accumulate(c[0], c[1], c[2]);
      accumulate(c[0], c[2], c[3]);
    }
  }

  p.positions.resize(3 * ng);
  p.normals.resize(3 * ng);
  p.tangents.resize(4 * ng);
  p.texcoords.resize(2 * ng);
  for (std::size_t g = 0; g < ng; ++g) {
    const Vec3& x = m.positions[source[g]];
    const Vec3& n = normal[source[g]];
    Vec3 t = tan[g] - n * dot(n, tan[g]);
    const double tl = length(t);
    t = tl > 1e-30 && std::isfinite(tl) ? t / tl : orthogonal(n);
    const double w = dot(cross(n, t), bit[g]) < 0 ? -1.0 : 1.0;
    p.positions[3 * g] = static_cast<float>(x.x);
    p.positions[3 * g + 1] = static_cast<float>(x.y);
    p.positions[3 * g + 2] = static_cast<float>(x.z);
    p.normals[3 * g] = static_cast<float>(n.x);
    p.normals[3 * g + 1] = static_cast<float>(n.y);
    p.normals[3 * g + 2] = static_cast<float>(n.z);
    p.tangents[4 * g] = static_cast<float>(t.x);
    p.tangents[4 * g + 1] = static_cast<float>(t.y);
    p.tangents[4 * g + 2] = static_cast<float>(t.z);
    p.tangents[4 * g + 3] = static_cast<float>(w);
    p.texcoords[2 * g] = static_cast<float>(uv[g].u);
    p.texcoords[2 * g + 1] = static_cast<float>(uv[g].v);
  }
  return p;
}

}  // namespace sylva::mesh
