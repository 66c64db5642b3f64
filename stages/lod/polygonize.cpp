// Polygonisation with the edge function h(rho).
// Seed: Zhang et al. 2017, §5.1 (eq. 6–10, vertex connection cases i–iii), §5.2 (eq. 11, 12),
// §5.5 (three lines with spread normals), Appendix A.2 (eq. A4, A5).
#include "stages/lod/polygonize.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sylva::lod {

int edge_count(double rho, int max_edges) {
  if (!(rho < 2)) return 1;  // also R = 0 (rho = inf) and NaN-safe
  if (rho >= 0.5) return 3;
  if (rho <= 0) return max_edges;
  // Eq. (9): h = i + 1 for P_{i+1} <= rho < P_i, i.e. the smallest h with P_h <= rho, which is
  // ceil(h^(rho)) of eq. (8) (eq. 7's floor + 1 differs only exactly at the steps P_i).
  const double h = std::ceil(std::numbers::pi / std::acos(1 - rho) - 1e-9);
  return static_cast<int>(std::clamp(h, 3.0, static_cast<double>(max_edges)));
}

double line_alpha(double rho) { return rho >= 2 ? 2 / rho : 1.0; }

namespace {

void push3(std::vector<float>& v, Vec3 a) {
  v.push_back(static_cast<float>(a.x));
  v.push_back(static_cast<float>(a.y));
  v.push_back(static_cast<float>(a.z));
}

// Ring of h vertices at skeletal vector s (eq. A4 with angle 2*pi*j/h, normals A5), at
// ring_factor(h) R from the axis: the prism keeps the cylinder's mean width (polygonize.h).
std::uint32_t emit_ring(const SkeletalVector& s, int h, BranchGeometry& out) {
  const auto base = static_cast<std::uint32_t>(out.tri_positions.size() / 3);
  const double radius = ring_factor(h) * s.r;
  for (int j = 0; j < h; ++j) {
    const double a = 2 * std::numbers::pi * j / h;
    const Vec3 d = s.n * std::cos(a) + s.b * std::sin(a);
    push3(out.tri_positions, s.p + d * radius);
    push3(out.tri_normals, d);
  }
  out.ring_edges.push_back(h);
  out.max_polygon_error = std::max(out.max_polygon_error, polygon_error(s.r, h));
  return base;
}

// Eq. (12) at one node of a line: 2 / rho with rho = E3 / R_k (1 where rho < 2).
double node_alpha(double r, double e3) {
  return line_alpha(r > 0 ? e3 / r : std::numeric_limits<double>::infinity());
}

void tri(BranchGeometry& out, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  out.tri_indices.insert(out.tri_indices.end(), {a, b, c});
}

// Cases (ii) and (iii): ring a (na vertices at the lower node) to ring b (nb at the upper node).
// The larger ring's edges are walked once; an edge whose Bresenham step advances on the smaller
// ring becomes a quad, the others triangles: exactly f quads and d triangles, evenly spread.
void connect_rings(BranchGeometry& out, std::uint32_t a, int na, std::uint32_t b, int nb) {
  const bool a_larger = na >= nb;
  const int nl = a_larger ? na : nb, ns = a_larger ? nb : na;
  const std::uint32_t l = a_larger ? a : b, s = a_larger ? b : a;
  for (int e = 0; e < nl; ++e) {
    const int j0 = e * ns / nl, j1 = (e + 1) * ns / nl;
    const std::uint32_t l0 = l + e, l1 = l + (e + 1) % nl, s0 = s + j0 % ns, s1 = s + j1 % ns;
    // The step's corners on ring a and on ring b; the smaller ring's two are one where it does
    // not advance, and the quad's first (a larger) or second (b larger) triangle is left.
    const std::uint32_t a0 = a_larger ? l0 : s0, a1 = a_larger ? l1 : s1;
    const std::uint32_t b0 = a_larger ? s0 : l0, b1 = a_larger ? s1 : l1;
    if (j1 > j0) {
      tri(out, a0, a1, b1);
      tri(out, a0, b1, b0);
      ++out.quads;
    } else {
      if (a_larger)
        tri(out, a0, a1, b1);
      else
        tri(out, a0, b1, b0);
      ++out.triangles;
    }
  }
}

}  // namespace

void polygonize_branch(std::span<const SkeletalVector> g, std::span<const std::uint32_t> kept, double e3,
                       int max_edges, BranchGeometry& out, std::span<const double> extra_alpha12) {
  const std::size_t n = kept.size();
  if (n < 2) return;
  auto alpha_at = [&](std::size_t i) {
    return node_alpha(g[kept[i]].r, e3) + (extra_alpha12.empty() ? 0.0 : extra_alpha12[i]);
  };
  // 1. End polygons: H_k = h(E3 / R_k) per kept node (eq. 10, 11).
  auto edges_at = [&](std::size_t i) {
    const double r = g[kept[i]].r;
    return edge_count(r > 0 ? e3 / r : 2.0, max_edges);
  };
  int ha = edges_at(0);
  std::uint32_t ring_a = 0;
  bool have_ring_a = false;
  // Line chains share one vertex per node and copy (3 copies, normals 120° apart).
  std::uint32_t line_base = 0;
  std::size_t line_node = static_cast<std::size_t>(-1);
  // 2. Internodes, lower to upper.
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const SkeletalVector& sa = g[kept[i]];
    const SkeletalVector& sb = g[kept[i + 1]];
    const int hb = edges_at(i + 1);
    if (ha >= 3) {
      if (!have_ring_a) ring_a = emit_ring(sa, ha, out);
      ++out.mesh_internodes;
      if (hb >= 3) {
        // Cases (ii) prism (d = 0) and (iii) prismoid (d triangles + f quads).
        const std::uint32_t ring_b = emit_ring(sb, hb, out);
        connect_rings(out, ring_a, ha, ring_b, hb);
        ring_a = ring_b;
        have_ring_a = true;
      } else {
        // Case (i): f = 0, d = H_k >= 3: a fan of H_k triangles to the node where lines start.
        const auto apex = static_cast<std::uint32_t>(out.tri_positions.size() / 3);
        push3(out.tri_positions, sb.p);
        push3(out.tri_normals, sb.t);
        for (int j = 0; j < ha; ++j)
          tri(out, ring_a + static_cast<std::uint32_t>(j), ring_a + static_cast<std::uint32_t>((j + 1) % ha),
              apex);
        out.triangles += static_cast<std::size_t>(ha);
        have_ring_a = false;
      }
    } else {
      // Lines (h = 1): three segments with spread normals; alpha by eq. (12) at the thicker end.
      if (line_node != i) {
        line_base = static_cast<std::uint32_t>(out.line_positions.size() / 3);
        for (int c = 0; c < 3; ++c) {
          const double a = 2 * std::numbers::pi * c / 3;
          push3(out.line_positions, sa.p);
          push3(out.line_normals, sa.n * std::cos(a) + sa.b * std::sin(a));
          out.line_radii.push_back(static_cast<float>(sa.r));
          out.line_alpha12.push_back(static_cast<float>(alpha_at(i)));
        }
      }
      const auto next = static_cast<std::uint32_t>(out.line_positions.size() / 3);
      for (int c = 0; c < 3; ++c) {
        const double a = 2 * std::numbers::pi * c / 3;
        push3(out.line_positions, sb.p);
        push3(out.line_normals, sb.n * std::cos(a) + sb.b * std::sin(a));
        out.line_radii.push_back(static_cast<float>(sb.r));
        out.line_alpha12.push_back(static_cast<float>(alpha_at(i + 1)));
        out.line_indices.push_back(line_base + static_cast<std::uint32_t>(c));
        out.line_indices.push_back(next + static_cast<std::uint32_t>(c));
      }
      line_base = next;
      line_node = i + 1;
      out.lines += 3;
      ++out.line_internodes;
      const double r = std::max(sa.r, sb.r);
      const double len = length(sb.p - sa.p);
      out.alpha_length += line_alpha(r > 0 ? e3 / r : std::numeric_limits<double>::infinity()) * len;
      out.line_length += len;
      have_ring_a = false;
    }
    ha = hb;
  }
}

}  // namespace sylva::lod
