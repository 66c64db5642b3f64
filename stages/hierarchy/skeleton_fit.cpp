// Slicing a tube into circles. A first ordering of the points along the part comes from their
// geodesic distance to the base loop (Dijkstra over the mesh edges, so a curved branch is
// followed around its bend); bin centroids give a first centre line. Geodesic bins are tilted on
// a bend (the inner side is shorter than the outer), so each round then projects every point
// onto the current centre line, bins by that arc length (orthogonal slices), and fits a circle
// per bin in the plane orthogonal to the line there (Kasa's algebraic least squares, exact for
// points on a circle). Points beyond the line's ends extrapolate along the end segments.
#include "stages/hierarchy/skeleton_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <queue>

#include "stages/hierarchy/part_geometry.h"

namespace sylva::hierarchy {

using tree::Vec3;

namespace {

std::vector<double> geodesic_from(const Part& part, const std::vector<std::uint32_t>& sources) {
  const std::size_t n = part.points.size();
  std::vector<std::vector<std::uint32_t>> adj(n);
  for (const auto& t : part.triangles)
    for (int k = 0; k < 3; ++k) {
      adj[t[static_cast<std::size_t>(k)]].push_back(t[static_cast<std::size_t>((k + 1) % 3)]);
      adj[t[static_cast<std::size_t>((k + 1) % 3)]].push_back(t[static_cast<std::size_t>(k)]);
    }
  std::vector<double> dist(n, INFINITY);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (std::uint32_t s : sources) {
    dist[s] = 0;
    queue.emplace(0.0, s);
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    for (std::uint32_t w : adj[v]) {
      const double nd = d + length(part.points[w] - part.points[v]);
      if (nd < dist[w]) {
        dist[w] = nd;
        queue.emplace(nd, w);
      }
    }
  }
  return dist;
}

// Arc length of the closest point of the polyline to p; before the first and past the last
// node the end segments extend.
double project(const std::vector<Vec3>& line, const std::vector<double>& arc, Vec3 p) {
  double best_d = INFINITY, best_s = 0;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Vec3 seg = line[i + 1] - line[i];
    const double len2 = dot(seg, seg);
    double t = len2 > 0 ? dot(p - line[i], seg) / len2 : 0;
    if (i > 0) t = std::max(t, 0.0);
    if (i + 2 < line.size()) t = std::min(t, 1.0);
    const Vec3 q = line[i] + seg * t;
    const double d = dot(p - q, p - q);
    if (d < best_d) {
      best_d = d;
      best_s = arc[i] + t * std::sqrt(len2);
    }
  }
  return best_s;
}

struct Circle {
  double cx = 0, cy = 0, r = 0;
};

// Kasa fit: minimise sum (x^2 + y^2 + D x + E y + F)^2; the mean and mean distance when the
// points do not determine a circle (fewer than 3, or collinear).
Circle fit_circle(const std::vector<std::array<double, 2>>& pts) {
  Circle c;
  for (const auto& p : pts) {
    c.cx += p[0] / static_cast<double>(pts.size());
    c.cy += p[1] / static_cast<double>(pts.size());
  }
  if (pts.size() >= 3) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (const auto& p : pts) {
      const double x = p[0] - c.cx, y = p[1] - c.cy;  // centred: better conditioned
      const Eigen::Vector3d row(x, y, 1);
      a += row * row.transpose();
      b -= row * (x * x + y * y);
    }
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(a);
    if (lu.rank() == 3) {
      const Eigen::Vector3d s = lu.solve(b);
      const double r2 = s(0) * s(0) / 4 + s(1) * s(1) / 4 - s(2);
      // A near-collinear set (a sliver of an arc seen edge-on) fits a huge circle far away:
      // keep a fit only when its centre is within the points' reach of their mean.
      double reach = 0;
      for (const auto& p : pts) reach = std::max(reach, std::hypot(p[0] - c.cx, p[1] - c.cy));
      const double dx = -s(0) / 2, dy = -s(1) / 2;
      if (r2 > 0 && std::isfinite(r2) && std::hypot(dx, dy) <= reach && std::sqrt(r2) <= 2 * reach)
        return {c.cx + dx, c.cy + dy, std::sqrt(r2)};
    }
  }
  for (const auto& p : pts) c.r += std::hypot(p[0] - c.cx, p[1] - c.cy) / static_cast<double>(pts.size());
  return c;
}

std::vector<double> arc_lengths(const std::vector<Vec3>& line) {
  std::vector<double> arc(line.size(), 0);
  for (std::size_t i = 1; i < line.size(); ++i) arc[i] = arc[i - 1] + length(line[i] - line[i - 1]);
  return arc;
}

// Point and unit tangent of the polyline at arc length s (extrapolated past the ends).
std::pair<Vec3, Vec3> at_arc(const std::vector<Vec3>& line, const std::vector<double>& arc, double s) {
  std::size_t i = 0;
  while (i + 2 < line.size() && arc[i + 1] < s) ++i;
  const double len = arc[i + 1] - arc[i];
  const Vec3 dir = normalized(line[i + 1] - line[i]);
  return {line[i] + dir * (s - arc[i]), len > 0 ? dir : Vec3{0, 1, 0}};
}

// Slices of the points by `s`, about `width` long each, in order of s. A slice ends once it is
// `width` long at the next gap in s wider than a tenth of `width` (so a ring of a tube, whose
// points share one s, is never cut in two), or at 1.5 `width` whatever the gaps (a dense
// irregular mesh has no gaps).
std::vector<std::vector<std::uint32_t>> slices_by(const std::vector<double>& s, double width) {
  std::vector<std::uint32_t> order(s.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return s[a] < s[b]; });
  std::vector<std::vector<std::uint32_t>> bins;
  double start = -INFINITY;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const double v = s[order[k]];
    const bool long_enough = v - start >= width;
    const bool gap = k > 0 && v - s[order[k - 1]] > 0.1 * width;
    if (bins.empty() || (long_enough && gap) || v - start >= 1.5 * width) {
      bins.emplace_back();
      start = v;
    }
    bins.back().push_back(order[k]);
  }
  return bins;
}

// One round: the points sliced by `s`; a circle per slice.
SkeletonFit slice_round(const Part& part, const std::vector<double>& s, double width,
                        const std::vector<Vec3>& line, const std::vector<double>& arc) {
  const auto bins = slices_by(s, width);
  SkeletonFit fit;
  double sq = 0;
  for (const auto& bin : bins) {
    if (bin.empty()) continue;
    double mean_s = 0;
    for (std::uint32_t i : bin) mean_s += s[i] / static_cast<double>(bin.size());
    const auto [origin, axis] = at_arc(line, arc, mean_s);
    const Vec3 helper = std::abs(axis.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    const Vec3 u = normalized(cross(axis, helper)), w = cross(axis, u);
    std::vector<std::array<double, 2>> pts;
    for (std::uint32_t i : bin)
      pts.push_back({dot(part.points[i] - origin, u), dot(part.points[i] - origin, w)});
    const Circle c = fit_circle(pts);
    for (const auto& p : pts) sq += std::pow(std::hypot(p[0] - c.cx, p[1] - c.cy) - c.r, 2);
    fit.nodes.push_back({origin + u * c.cx + w * c.cy, c.r});
  }
  fit.rms_residual = std::sqrt(sq / static_cast<double>(part.points.size()));
  return fit;
}

// Appends p unless it is within `gap` of the last point: a centre line's segments need a
// direction (the base bin's centroid is the base point itself).
void push_distinct(std::vector<Vec3>& line, Vec3 p, double gap) {
  if (line.empty() || length(p - line.back()) > gap) line.push_back(p);
}

SkeletonFit axis_fallback(const Part& part, const BranchBase& base) {
  // From the base towards the centroid: a stub shorter than it is wide has its largest principal
  // axis across, not along it.
  const Principal pc = principal_axes(part.points);
  Vec3 axis = pc.axes[0];
  const Vec3 to_centroid = pc.centroid - base.point;
  if (length(to_centroid) > 1e-9) axis = normalized(to_centroid);
  double reach = 0;
  for (const Vec3& p : part.points) reach = std::max(reach, dot(p - base.point, axis));
  if (reach <= 0) reach = std::max(pc.extent[0], 1e-6);
  const double r = base.radius > 0 ? base.radius : (pc.extent[1] + pc.extent[2]) / 4;
  SkeletonFit fit;
  fit.nodes = {{base.point, r}, {base.point + axis * reach, r}};
  fit.axis_fallback = true;
  return fit;
}

}  // namespace

SkeletonFit fit_skeleton(const Part& part, const BranchBase& base, const FitOptions& o) {
  // 1. Order the points by geodesic distance from the base loop (or base vertex).
  std::vector<std::uint32_t> sources = base.loop;
  if (sources.empty()) {
    std::uint32_t nearest = 0;
    for (std::uint32_t i = 1; i < part.points.size(); ++i)
      if (length(part.points[i] - base.point) < length(part.points[nearest] - base.point)) nearest = i;
    sources.push_back(nearest);
  }
  std::vector<double> s = geodesic_from(part, sources);
  for (double& d : s)
    if (!std::isfinite(d)) d = 0;  // unreachable (cannot happen in a connected part)
  const double reach = *std::max_element(s.begin(), s.end());

  // 2. Slice count: slices of about `slice_radii` base radii.
  const Principal pc = principal_axes(part.points);
  const double r0 = base.radius > 0 ? base.radius : (pc.extent[1] + pc.extent[2]) / 4;
  if (!(r0 > 0) || reach <= 0) return axis_fallback(part, base);
  const double slices = std::min(reach / (o.slice_radii * r0), static_cast<double>(o.max_slices));
  const auto n = static_cast<std::size_t>(std::lround(slices));
  if (n < 2) return axis_fallback(part, base);

  // 3. A first centre line from the geodesic bins' centroids, from the base point.
  const double width = reach / static_cast<double>(n);
  std::vector<Vec3> line{base.point};
  for (const auto& bin : slices_by(s, width)) {
    Vec3 sum;
    for (std::uint32_t i : bin) sum += part.points[i];
    push_distinct(line, sum / static_cast<double>(bin.size()), 0.25 * r0);
  }
  if (line.size() < 2) return axis_fallback(part, base);

  // 4. Rounds: project onto the line, slice orthogonally, fit circles; the centres are the next
  //    round's line.
  SkeletonFit fit;
  for (int round = 0; round <= o.iterations; ++round) {
    const std::vector<double> arc = arc_lengths(line);
    for (std::size_t i = 0; i < part.points.size(); ++i) s[i] = project(line, arc, part.points[i]);
    fit = slice_round(part, s, width, line, arc);
    if (fit.nodes.size() < 2) return axis_fallback(part, base);
    line.clear();
    for (const tree::Node& node : fit.nodes) push_distinct(line, node.position, 0.25 * r0);
    if (line.size() < 2) return axis_fallback(part, base);
  }
  return fit;
}

}  // namespace sylva::hierarchy
