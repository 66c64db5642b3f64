// Leaf cards and needles (foliage.h). Seed: Nystad 2010 §5.5.4 (leaf quads from point, direction,
// orientation, length, width and texture quadrant).
#include "stages/mesh/foliage.h"

#include <cmath>

#include "libs/tree/foliage.h"

namespace sylva::mesh {
namespace {

using tree::Vec3;

void push3(std::vector<float>& v, Vec3 a) {
  v.push_back(static_cast<float>(a.x));
  v.push_back(static_cast<float>(a.y));
  v.push_back(static_cast<float>(a.z));
}

Vec3 orthogonal(Vec3 n) {
  const Vec3 a = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return tree::normalized(tree::cross(n, a));
}

}  // namespace

gltf::Primitive leaf_cards(const tree::Tree& tree) {
  gltf::Primitive p;
  p.mode = gltf::PrimitiveMode::kTriangles;
  const std::size_t n = tree.leaves.size();
  p.positions.reserve(12 * n);
  p.normals.reserve(12 * n);
  p.texcoords.reserve(8 * n);
  p.indices.reserve(6 * n);
  for (const tree::Leaf& leaf : tree.leaves) {
    const Vec3 d = tree::normalized(tree::to_double(leaf.direction));
    Vec3 nrm = tree::to_double(leaf.normal);
    nrm = tree::normalized(nrm - d * tree::dot(nrm, d));
    const Vec3 s = tree::cross(nrm, d);  // unit: nrm and d are orthonormal
    const Vec3 base = tree::to_double(leaf.position);
    const Vec3 half = s * (0.5 * leaf.width);
    const Vec3 along = d * static_cast<double>(leaf.length);
    const tree::UvRect cell = tree::atlas_cell(tree.materials, leaf.variant);
    const auto first = static_cast<std::uint32_t>(p.positions.size() / 3);
    // A: petiole, -s side; B: petiole, +s; C: tip, +s; D: tip, -s.
    push3(p.positions, base - half);
    push3(p.positions, base + half);
    push3(p.positions, base + half + along);
    push3(p.positions, base - half + along);
    p.texcoords.insert(p.texcoords.end(),
                       {cell.u0, cell.v0, cell.u1, cell.v0, cell.u1, cell.v1, cell.u0, cell.v1});
    for (int k = 0; k < 4; ++k) push3(p.normals, nrm);
    // (A, B, C) would face -n (s x d = -n): list the corners the other way round.
    p.indices.insert(p.indices.end(), {first, first + 2, first + 1, first, first + 3, first + 2});
  }
  return p;
}

gltf::Primitive needle_geometry(const tree::Tree& tree) {
  gltf::Primitive p;
  p.mode = gltf::PrimitiveMode::kTriangles;
  const std::size_t n = tree.needles.size();
  p.positions.reserve(12 * n);
  p.normals.reserve(12 * n);
  p.indices.reserve(12 * n);
  for (const tree::Needle& nd : tree.needles) {
    const Vec3 base = tree::to_double(nd.base), tip = tree::to_double(nd.tip);
    Vec3 a = tree::normalized(tip - base);
    if (tree::length(a) == 0) a = Vec3{0, 1, 0};
    const Vec3 e1 = orthogonal(a);
    const Vec3 e2 = tree::cross(a, e1);
    const auto first = static_cast<std::uint32_t>(p.positions.size() / 3);
    for (int k = 0; k < 3; ++k) {
      const double th = 2.0943951023931953 * k;  // 120 degrees
      const Vec3 radial = e1 * std::cos(th) + e2 * std::sin(th);
      push3(p.positions, base + radial * static_cast<double>(nd.radius));
      push3(p.normals, tree::normalized(radial));
    }
    push3(p.positions, tip);
    push3(p.normals, a);
    const std::uint32_t b0 = first, b1 = first + 1, b2 = first + 2, t = first + 3;
    p.indices.insert(p.indices.end(), {b0, b1, t, b1, b2, t, b2, b0, t, b0, b2, b1});
  }
  return p;
}

}  // namespace sylva::mesh
