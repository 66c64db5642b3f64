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

// Error of an inscribed h-gon for radius r (the distance from an edge to the circle, §5.1).
inline double polygon_error(double r, int h) { return h >= 3 ? r * (1 - std::cos(3.14159265358979323846 / h)) : r; }

// Geometry of one level's branches (or needles), ready for glTF.
struct BranchGeometry {
  std::vector<float> tri_positions, tri_normals;  // xyz per vertex
  std::vector<std::uint32_t> tri_indices;         // triangles (a quad is two)
  std::vector<float> line_positions, line_normals;
  std::vector<float> line_radii;                  // R_k of the node of each line vertex, m
  std::vector<std::uint32_t> line_indices;        // segments
  std::size_t quads = 0;            // quads emitted (prisms and prismoids)
  std::size_t triangles = 0;        // triangles emitted (prismoids and fan covers)
  std::size_t lines = 0;            // line segments emitted (3 per line internode)
  std::size_t mesh_internodes = 0;  // internodes drawn as polygons
  std::size_t line_internodes = 0;  // internodes drawn as lines
  double alpha_length = 0;          // sum of alpha * length over line internodes
  double line_length = 0;           // sum of length over line internodes
  double max_polygon_error = 0;     // max over rings of polygon_error(R_k, H_k), m
  std::vector<int> ring_edges;      // H_k of every ring emitted (tests and statistics)

  // Length-weighted mean alpha of the lines (1 when there are none): the level's alpha (§6:
  // one transparency per level).
  double level_alpha() const { return line_length > 0 ? alpha_length / line_length : 1.0; }
};

// Polygonises one branch given the kept node indices of merge_internodes() (>= 2, increasing).
void polygonize_branch(std::span<const SkeletalVector> g, std::span<const std::uint32_t> kept, double e3,
                       int max_edges, BranchGeometry& out);

}  // namespace sylva::lod
