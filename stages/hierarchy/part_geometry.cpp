// Shared geometry of parts. Boundary loops are the open ends of tubes: the refinement of Celba's
// branch significant point (significant_point.cpp) and the seeds of the skeleton's slicing
// (skeleton_fit.cpp) both start from them.
#include "stages/hierarchy/part_geometry.h"

#include <Eigen/Dense>
#include <algorithm>
#include <map>

namespace sylva::hierarchy {

using tree::Vec3;

Principal principal_axes(const std::vector<Vec3>& points) {
  Principal r;
  r.axes = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  if (points.empty()) return r;
  for (const Vec3& p : points) r.centroid += p;
  r.centroid = r.centroid / static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) {
    const Eigen::Vector3d d(p.x - r.centroid.x, p.y - r.centroid.y, p.z - r.centroid.z);
    cov += d * d.transpose();
  }
  if (cov.trace() <= 0) return r;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  for (int k = 0; k < 3; ++k) {  // eigenvalues ascend: axis k is column 2 - k
    const Eigen::Vector3d a = es.eigenvectors().col(2 - k);
    Vec3 axis{a.x(), a.y(), a.z()};
    // A deterministic sign: the largest component positive.
    const double m[3] = {std::abs(axis.x), std::abs(axis.y), std::abs(axis.z)};
    const int big = m[0] >= m[1] && m[0] >= m[2] ? 0 : (m[1] >= m[2] ? 1 : 2);
    const double c = big == 0 ? axis.x : (big == 1 ? axis.y : axis.z);
    r.axes[static_cast<std::size_t>(k)] = normalized(c < 0 ? -axis : axis);
  }
  for (std::size_t k = 0; k < 3; ++k) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Vec3& p : points) {
      const double s = dot(p - r.centroid, r.axes[k]);
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    r.extent[k] = hi - lo;
  }
  return r;
}

std::vector<std::vector<std::uint32_t>> boundary_loops(const Part& part) {
  // Undirected edge -> number of triangles; then each boundary edge directed as its triangle has
  // it, so a walk follows the boundary consistently.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : part.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  std::multimap<std::uint32_t, std::uint32_t> next;  // boundary edges a -> b
  for (const auto& t : part.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      if (uses[{std::min(a, b), std::max(a, b)}] == 1) next.emplace(a, b);
    }
  std::vector<std::vector<std::uint32_t>> loops;
  while (!next.empty()) {
    auto it = next.begin();  // lowest start: loops in order of their lowest point
    const std::uint32_t start = it->first;
    std::vector<std::uint32_t> loop{start};
    std::uint32_t at = it->second;
    next.erase(it);
    while (at != start) {
      loop.push_back(at);
      const auto n = next.find(at);
      if (n == next.end()) break;  // non-manifold: the walk ends here
      at = n->second;
      next.erase(n);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

LoopShape loop_shape(const Part& part, const std::vector<std::uint32_t>& loop) {
  LoopShape s;
  for (std::uint32_t i : loop) s.centroid += part.points[i];
  s.centroid = s.centroid / static_cast<double>(loop.size());
  for (std::uint32_t i : loop) s.radius += length(part.points[i] - s.centroid);
  s.radius /= static_cast<double>(loop.size());
  return s;
}

}  // namespace sylva::hierarchy
