// Polygonisation of merged internodes: H-gon prisms, prismoids, fan covers and lines.
//
// Seed: Zhang et al. 2017, §5.1–5.2 and §5.5 (lines with spread normals), Appendix A.2
// (vertices A4, normals A5):
//   - end polygons: H_k = h(E3 / R_k), the edge function of eq. (11) (eq. 9 extended by h = 1,
//     a line, for rho >= 2), clamped to the maximum edge count H;
//   - internode with both ends polygons: a prism of H quads (d_k = 0) or a prismoid of d_k
//     triangles and f_k quads, the triangles spread evenly around the ring (no slivers);
//   - internode from a polygon to a line end (f_k = 0, d_k >= 3): a fan cover of H_k triangles
//     closing the mesh at the node where the line starts;
//   - internode whose first end is a line: three line segments with normals 120° apart (§5.5),
//     alpha = 2 / rho (eq. 12) with rho taken at the thicker end.
// Pure; appends into caller-owned buffers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "stages/lod/internodes.h"

namespace sylva::lod {

// Eq. (11): 1 (line) for rho >= 2, 3 for 0.5 <= rho < 2, floor(pi / acos(1 - rho)) + 1 below,
// clamped to [3, max_edges]; max_edges (H) >= 3. rho = E3 / R; R = 0 gives a line.
int edge_count(double rho, int max_edges);

// Eq. (12): 2 / rho for rho >= 2, else 1.
double line_alpha(double rho);

// Circumradius factor of the ring polygons: a regular h-gon of circumradius k R has the mean
// width (perimeter / pi, Cauchy) of the circle of radius R, so a prism covers on average what
// the cylinder covers; k = pi / (h sin(pi/h)) (1.209 for h = 3, 1.0115 for h = 12).
inline double ring_factor(int h) {
  constexpr double pi = 3.14159265358979323846;
  return h >= 3 ? pi / (h * std::sin(pi / h)) : 1.0;
}

// Largest distance between the ring h-gon (circumradius ring_factor(h) R) and the circle of
// radius r: its corners lie (k - 1) r outside, its edge midpoints r (1 - k cos(pi/h)) inside.
// Below the inscribed polygon's r (1 - cos(pi/h)) for every h >= 3, so eq. (9)'s choice of h
// still bounds it by E3.
inline double polygon_error(double r, int h) {
  if (h < 3) return r;
  const double k = ring_factor(h);
  return r * std::max(k - 1, 1 - k * std::cos(3.14159265358979323846 / h));
}

// Geometry of one level's branches (or needles), ready for glTF.
struct BranchGeometry {
  std::vector<float> tri_positions, tri_normals;  // xyz per vertex
  std::vector<std::uint32_t> tri_indices;         // triangles (a quad is two)
  std::vector<float> line_positions, line_normals;
  std::vector<float> line_radii;  // R_k of the node of each line vertex, m
  // Eq. (12)'s alpha 2/rho = 2 R_k / E3 of each line vertex (<= 1), plus the coverage of
  // decimated subtrees carried onto it (chain.cpp, "coverage of decimated branches"); the
  // drawn alpha is drawn_line_alpha(this, delta) (chain.h).
  std::vector<float> line_alpha12;
  std::vector<std::uint32_t> line_indices;  // segments
  std::size_t quads = 0;                    // quads emitted (prisms and prismoids)
  std::size_t triangles = 0;                // triangles emitted (prismoids and fan covers)
  std::size_t lines = 0;                    // line segments emitted (3 per line internode)
  std::size_t mesh_internodes = 0;          // internodes drawn as polygons
  std::size_t line_internodes = 0;          // internodes drawn as lines
  double alpha_length = 0;                  // sum of alpha * length over line internodes
  double line_length = 0;                   // sum of length over line internodes
  double max_polygon_error = 0;             // max over rings of polygon_error(R_k, H_k), m
  std::vector<int> ring_edges;              // H_k of every ring emitted (tests and statistics)

  // Length-weighted mean alpha of the lines (1 when there are none): the level's alpha (§6:
  // reported; the drawn alpha is per vertex, line_alpha12).
  double level_alpha() const { return line_length > 0 ? alpha_length / line_length : 1.0; }
};

// Polygonises one branch given the kept node indices of merge_internodes() (>= 2, increasing).
// `extra_alpha12` (empty, or one value per kept node) is added to eq. (12)'s alpha of the line
// vertices at those nodes (the coverage of decimated subtrees, chain.cpp).
void polygonize_branch(std::span<const SkeletalVector> g, std::span<const std::uint32_t> kept, double e3,
                       int max_edges, BranchGeometry& out, std::span<const double> extra_alpha12 = {});

}  // namespace sylva::lod
