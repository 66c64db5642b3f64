// Bark-versus-skeleton measurements (bark_metrics.h).
#include "stages/mesh/bark_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sylva::mesh {

namespace {

// The trunk's axis point and radius at height h (first crossing), or false.
bool trunk_at(const tree::Tree& tree, double h, Vec3& axis, double& radius) {
  if (tree.branches.empty()) return false;
  const auto& nodes = tree.branches.front().nodes;
  for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
    const double y0 = nodes[k].position.y, y1 = nodes[k + 1].position.y;
    if (y0 <= h && y1 >= h && y1 > y0) {
      const double f = (h - y0) / (y1 - y0);
      axis = nodes[k].position + (nodes[k + 1].position - nodes[k].position) * f;
      radius = nodes[k].radius + (nodes[k + 1].radius - nodes[k].radius) * f;
      return true;
    }
  }
  return false;
}

}  // namespace

double skeleton_diameter(const tree::Tree& tree, double h) {
  Vec3 a;
  double r = 0;
  return trunk_at(tree, h, a, r) ? 2 * r : 0.0;
}

double breast_height(const tree::Tree& tree, const std::vector<char>& omit, double nominal,
                     double min_diameter) {
  if (tree.branches.empty()) return -1;
  const double base = tree.branches.front().nodes.front().position.y;
  // Height spans of the trunk's children's joints.
  std::vector<std::pair<double, double>> joints;
  for (std::size_t i = 0; i < tree.branches.size(); ++i) {
    const tree::Branch& b = tree.branches[i];
    if (b.parent != 0 || (i < omit.size() && omit[i])) continue;
    const double y = tree::attachment_point(tree, b).y;
    const double reach = 1.5 * b.nodes.front().radius;
    joints.emplace_back(y - reach, y + reach);
  }
  auto clear = [&](double y) {
    for (const auto& [lo, hi] : joints)
      if (y >= lo && y <= hi) return false;
    return skeleton_diameter(tree, y) >= min_diameter;
  };
  for (int step = 0; step <= 50; ++step) {
    for (const double y : {base + nominal - 0.01 * step, base + nominal + 0.01 * step})
      if (y > base && clear(y)) return y - base;
  }
  return -1;
}

double trunk_section_diameter(const QuadMesh& mesh, const tree::Tree& tree, double h) {
  Vec3 axis;
  double r = 0;
  if (!trunk_at(tree, h, axis, r)) return 0;
  const double reach2 = std::pow(2.5 * r + 0.05, 2);
  double twice_area = 0;
  auto triangle = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
    // The segment where y = h cuts the triangle.
    const Vec3 v[3] = {a, b, c};
    Vec3 cut[2];
    int n = 0;
    for (int i = 0; i < 3 && n < 2; ++i) {
      const Vec3 p = v[i], q = v[(i + 1) % 3];
      if ((p.y < h) != (q.y < h)) cut[n++] = p + (q - p) * ((h - p.y) / (q.y - p.y));
    }
    if (n != 2) return;
    const Vec3 mid = (cut[0] + cut[1]) * 0.5;
    if (std::pow(mid.x - axis.x, 2) + std::pow(mid.z - axis.z, 2) > reach2) return;
    // The divergence theorem in the plane: A = 1/2 ∮ (p - axis) . m dl, m the outward normal of
    // the section's boundary = the triangle's outward normal projected onto the plane.
    const Vec3 nt = tree::cross(b - a, c - a);
    const double mx = nt.x, mz = nt.z, ml = std::sqrt(mx * mx + mz * mz);
    if (ml == 0) return;
    const double len = std::hypot(cut[1].x - cut[0].x, cut[1].z - cut[0].z);
    twice_area += len * ((mid.x - axis.x) * mx + (mid.z - axis.z) * mz) / ml;
  };
  for (const Quad& q : mesh.quads) {
    triangle(mesh.positions[q[0]], mesh.positions[q[1]], mesh.positions[q[2]]);
    triangle(mesh.positions[q[0]], mesh.positions[q[2]], mesh.positions[q[3]]);
  }
  const double area = std::abs(twice_area) / 2;
  return 2 * std::sqrt(area / std::numbers::pi);
}

double mesh_volume(const QuadMesh& mesh) {
  double v = 0;
  auto tri = [&](const Vec3& a, const Vec3& b, const Vec3& c) { v += tree::dot(a, tree::cross(b, c)); };
  for (const Quad& q : mesh.quads) {
    tri(mesh.positions[q[0]], mesh.positions[q[1]], mesh.positions[q[2]]);
    tri(mesh.positions[q[0]], mesh.positions[q[2]], mesh.positions[q[3]]);
  }
  return v / 6;
}

double skeleton_volume(const tree::Tree& tree, const std::vector<char>& omit, bool outside_parents,
                       double min_radius) {
  double v = 0;
  for (std::size_t i = 0; i < tree.branches.size(); ++i) {
    if (i < omit.size() && omit[i]) continue;
    const tree::Branch& b = tree.branches[i];
    const auto& nodes = b.nodes;
    // The parent's section at the attachment: a ball of its radius around the attachment point.
    Vec3 at{};
    double rp = 0;
    if (outside_parents && b.parent >= 0) {
      const tree::Branch& p = tree.branches[static_cast<std::size_t>(b.parent)];
      at = tree::attachment_point(tree, b);
      const double t = b.parent_t;
      const std::size_t k = b.parent_node;
      rp = k + 1 < p.nodes.size() ? p.nodes[k].radius + (p.nodes[k + 1].radius - p.nodes[k].radius) * t
                                  : p.nodes[k].radius;
    }
    // With outside_parents the polyline starts at the attachment point (the implicit joint
    // segment, at the child's first radius) and loses what lies inside the parent's ball.
    std::vector<tree::Node> poly;
    if (rp > 0) poly.push_back({at, nodes.front().radius});
    poly.insert(poly.end(), nodes.begin(), nodes.end());
    for (std::size_t k = 0; k + 1 < poly.size(); ++k) {
      const double l = tree::length(poly[k + 1].position - poly[k].position);
      const double a = std::max(poly[k].radius, min_radius), c = std::max(poly[k + 1].radius, min_radius);
      double outside = 1;
      if (rp > 0) {
        constexpr int kParts = 32;
        int n = 0;
        for (int j = 0; j < kParts; ++j) {
          const Vec3 x = poly[k].position + (poly[k + 1].position - poly[k].position) * ((j + 0.5) / kParts);
          n += tree::length(x - at) >= rp ? 1 : 0;
        }
        outside = static_cast<double>(n) / kParts;
      }
      v += outside * std::numbers::pi * l * (a * a + a * c + c * c) / 3;
    }
  }
  return v;
}

double lowest_point(const QuadMesh& mesh) {
  double y = std::numeric_limits<double>::infinity();
  for (const Vec3& p : mesh.positions) y = std::min(y, p.y);
  return y;
}

}  // namespace sylva::mesh
