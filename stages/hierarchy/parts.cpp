// Algorithm 1 of Celba 2007 (seed 000 §4.2.4, "Equivalence class finding algorithm"): every
// vertex starts in its own group; each triangle merges the groups of its three vertices. The
// thesis renumbers groups through a group -> vertices multimap; a union-find with path halving
// does the same merges in near-linear time. Before it, a weld pass (our addition, issue 37)
// maps vertices closer than the weld tolerance onto one, through a spatial hash of cells one
// tolerance wide (a match lies in the 27 cells around a vertex), so duplicated seam vertices
// and touching-but-unshared tubes connect as the modeller meant.
#include "stages/hierarchy/parts.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <unordered_map>

#include "stages/hierarchy/hierarchy_error.h"

namespace sylva::hierarchy {

namespace {

using tree::Vec3;

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};

// welded[i]: the source vertex that vertex i was welded onto (itself when none was close).
// Looking up is by hash; the answer is the lowest-numbered match, so the result does not depend
// on hash iteration order.
std::vector<std::uint32_t> weld(const std::vector<tree::Vec3f>& positions, double tol) {
  std::vector<std::uint32_t> welded(positions.size());
  std::iota(welded.begin(), welded.end(), 0u);
  if (tol <= 0) return welded;
  std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> cells;
  cells.reserve(positions.size());
  const double tol2 = tol * tol;
  auto cell_of = [&](const Vec3& p) {
    return CellKey{static_cast<std::int64_t>(std::floor(p.x / tol)),
                   static_cast<std::int64_t>(std::floor(p.y / tol)),
                   static_cast<std::int64_t>(std::floor(p.z / tol))};
  };
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    const Vec3 p = tree::to_double(positions[i]);
    const CellKey c = cell_of(p);
    std::uint32_t best = i;
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find({c.x + dx, c.y + dy, c.z + dz});
          if (it == cells.end()) continue;
          for (std::uint32_t j : it->second) {
            const Vec3 d = tree::to_double(positions[j]) - p;
            if (j < best && dot(d, d) <= tol2) best = j;
          }
        }
    welded[i] = best;
    if (best == i) cells[c].push_back(i);  // only representatives are searched
  }
  return welded;
}

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];  // path halving
    x = parent[x];
  }
  return x;
}

void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find(parent, a);
  b = find(parent, b);
  if (a == b) return;
  if (b < a) std::swap(a, b);
  parent[b] = a;  // the lower root wins: deterministic
}

void check_primitive(const tree::SourcePrimitive& p, std::size_t index) {
  const std::string who = "source primitive " + std::to_string(index) + " (\"" + p.name + "\")";
  if (p.indices.size() % 3 != 0)
    throw HierarchyError(who + ": " + std::to_string(p.indices.size()) + " indices is not a multiple of 3");
  for (std::size_t k = 0; k < p.indices.size(); ++k)
    if (p.indices[k] >= p.positions.size())
      throw HierarchyError(who + ": index " + std::to_string(p.indices[k]) + " at triangle " +
                           std::to_string(k / 3) + " is not below " + std::to_string(p.positions.size()) +
                           " positions");
  for (const tree::Vec3f& v : p.positions)
    if (!tree::is_finite(v)) throw HierarchyError(who + ": a position is not finite");
}

// Appends the parts of primitive `pi` to `out`.
void split_primitive(const tree::SourcePrimitive& prim, std::uint32_t pi, double tol,
                     std::vector<Part>& out) {
  const std::vector<std::uint32_t> welded = weld(prim.positions, tol);
  std::vector<std::uint32_t> parent(prim.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const std::size_t tris = prim.indices.size() / 3;
  for (std::size_t t = 0; t < tris; ++t) {
    const std::uint32_t a = welded[prim.indices[3 * t]], b = welded[prim.indices[3 * t + 1]],
                        c = welded[prim.indices[3 * t + 2]];
    unite(parent, a, b);
    unite(parent, a, c);
  }
  // Parts in the order of their first (non-degenerate) triangle; local points in first use.
  std::vector<std::int32_t> part_of_root(prim.positions.size(), -1);
  std::vector<std::int32_t> local(prim.positions.size(), -1);
  const std::size_t first = out.size();
  for (std::size_t t = 0; t < tris; ++t) {
    const std::array<std::uint32_t, 3> w{welded[prim.indices[3 * t]], welded[prim.indices[3 * t + 1]],
                                         welded[prim.indices[3 * t + 2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;  // degenerate after welding
    const std::uint32_t root = find(parent, w[0]);
    if (part_of_root[root] < 0) {
      part_of_root[root] = static_cast<std::int32_t>(out.size());
      out.push_back(Part{});
      out.back().primitive = pi;
    }
    Part& part = out[static_cast<std::size_t>(part_of_root[root])];
    std::array<std::uint32_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      if (local[w[k]] < 0) {
        local[w[k]] = static_cast<std::int32_t>(part.points.size());
        part.points.push_back(tree::to_double(prim.positions[w[k]]));
        part.face_count.push_back(0);
      }
      tri[k] = static_cast<std::uint32_t>(local[w[k]]);
      ++part.face_count[tri[k]];
    }
    part.triangles.push_back(tri);
  }
  // Texture v per welded point: the lowest over the source vertices welded into it.
  if (!prim.uvs.empty()) {
    for (std::size_t k = first; k < out.size(); ++k) out[k].min_v.assign(out[k].points.size(), INFINITY);
    for (std::size_t i = 0; i < prim.positions.size(); ++i) {
      const std::uint32_t w = welded[i];
      if (local[w] < 0) continue;
      Part& part = out[static_cast<std::size_t>(part_of_root[find(parent, w)])];
      float& v = part.min_v[static_cast<std::size_t>(local[w])];
      v = std::min(v, prim.uvs[i][1]);
    }
  }
  for (std::size_t k = first; k < out.size(); ++k) {
    Part& part = out[k];
    part.box_min = part.box_max = part.points.front();
    for (const Vec3& p : part.points) {
      part.box_min = {std::min(part.box_min.x, p.x), std::min(part.box_min.y, p.y),
                      std::min(part.box_min.z, p.z)};
      part.box_max = {std::max(part.box_max.x, p.x), std::max(part.box_max.y, p.y),
                      std::max(part.box_max.z, p.z)};
    }
  }
}

}  // namespace

std::vector<Part> split_parts(const tree::SourceGeometry& g, double weld_tolerance) {
  std::vector<Part> parts;
  for (std::size_t i = 0; i < g.primitives.size(); ++i) {
    check_primitive(g.primitives[i], i);
    split_primitive(g.primitives[i], static_cast<std::uint32_t>(i), weld_tolerance, parts);
  }
  return parts;
}

}  // namespace sylva::hierarchy
