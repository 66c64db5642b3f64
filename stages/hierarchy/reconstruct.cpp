// The hierarchy stage's core as a numbered recipe; each phase lives in its own file:
//   1. parts (parts.cpp, Algorithm 1), 2. branch or leaf (classify.cpp), 3. significant points
//   (significant_point.cpp), 4. hierarchy (connect.cpp, Algorithm 2), 5. skeletons
//   (skeleton_fit.cpp), joined here into a tree::Tree with one leaf quad per leaf part.
#include "stages/hierarchy/reconstruct.h"

#include <algorithm>
#include <numeric>

#include "stages/hierarchy/connect.h"
#include "stages/hierarchy/hierarchy_error.h"
#include "stages/hierarchy/part_geometry.h"
#include "stages/hierarchy/parts.h"

namespace sylva::hierarchy {

using tree::Vec3;

namespace {

// The closest point of a branch's polyline to p, as (node, t) with the tree's rule that t == 0
// at the last node.
std::pair<std::uint32_t, double> closest_on(const std::vector<tree::Node>& nodes, Vec3 p) {
  std::uint32_t best_node = 0;
  double best_t = 0, best_d = INFINITY;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
    const Vec3 a = nodes[i].position, seg = nodes[i + 1].position - a;
    const double len2 = dot(seg, seg);
    const double t = len2 > 0 ? std::clamp(dot(p - a, seg) / len2, 0.0, 1.0) : 0.0;
    const Vec3 q = a + seg * t;
    const double d = dot(p - q, p - q);
    if (d < best_d) {
      best_d = d;
      best_node = static_cast<std::uint32_t>(i);
      best_t = t;
    }
  }
  if (best_t >= 1.0) return {best_node + 1, 0.0};
  return {best_node, best_t};
}

Vec3 on_polyline(const std::vector<tree::Node>& nodes, std::pair<std::uint32_t, double> at) {
  const Vec3 a = nodes[at.first].position;
  if (at.second == 0) return a;
  return a + (nodes[at.first + 1].position - a) * at.second;
}

// A leaf quad fitted to a leaf part: its plane (the thinnest principal axis, facing the side its
// triangles wind to), its principal axis pointing away from where it grows, its extent.
tree::Leaf fit_leaf(const Part& part, Vec3 point, LeafPoint rule, const std::vector<tree::Node>& branch) {
  const Principal pc = principal_axes(part.points);
  Vec3 normal = pc.axes[2], dir = pc.axes[0];
  Vec3 wound;
  for (const auto& t : part.triangles)
    wound += cross(part.points[t[1]] - part.points[t[0]], part.points[t[2]] - part.points[t[0]]);
  if (dot(wound, normal) < 0) normal = -normal;
  const Vec3 from =
      rule == LeafPoint::kPetiole ? point : on_polyline(branch, closest_on(branch, pc.centroid));
  if (dot(pc.centroid - from, dir) < 0) dir = -dir;
  double lo = INFINITY, hi = -INFINITY, wlo = INFINITY, whi = -INFINITY;
  const Vec3 side = cross(normal, dir);
  for (const Vec3& p : part.points) {
    lo = std::min(lo, dot(p - point, dir));
    hi = std::max(hi, dot(p - point, dir));
    wlo = std::min(wlo, dot(p - point, side));
    whi = std::max(whi, dot(p - point, side));
  }
  // Petiole: the quad starts at the petiole; centroid: at the part's end nearest the branch.
  const double start = rule == LeafPoint::kPetiole ? 0.0 : lo;
  tree::Leaf leaf;
  leaf.position = tree::to_float(point + dir * start);
  leaf.direction = tree::to_float(dir);
  leaf.normal = tree::to_float(normal);
  leaf.length = static_cast<float>(std::max(hi - start, 1e-6));
  leaf.width = static_cast<float>(std::max(whi - wlo, 1e-6));
  return leaf;
}

double diagonal(const Part& p) { return length(p.box_max - p.box_min); }

// Mean base colour of the parts of one kind, weighted by triangles; unset (zero) when none.
tree::Color mean_color(const std::vector<Part>& parts, const std::vector<PartClass>& cls, PartKind kind,
                       const tree::SourceGeometry& g) {
  double r = 0, gr = 0, b = 0, w = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (cls[i].kind != kind) continue;
    const std::uint32_t m = g.primitives[parts[i].primitive].material;
    if (m >= g.materials.size()) continue;
    const auto& c = g.materials[m].base_color;
    const double n = static_cast<double>(parts[i].triangles.size());
    r += c[0] * n;
    gr += c[1] * n;
    b += c[2] * n;
    w += n;
  }
  if (w == 0) return {};
  return {static_cast<float>(r / w), static_cast<float>(gr / w), static_cast<float>(b / w)};
}

void check_input(const tree::Tree& in) {
  if (in.source.empty())
    throw HierarchyError(
        "the tree has no source geometry: stage hierarchy reconstructs a skeleton from an imported mesh");
  if (!in.branches.empty())
    throw HierarchyError("the tree already has a skeleton (" + std::to_string(in.branches.size()) +
                         " branches): stage hierarchy builds one from source geometry alone");
}

}  // namespace

Reconstruction reconstruct(const tree::Tree& in, const ReconstructOptions& o) {
  check_input(in);
  const tree::SourceGeometry& g = in.source;
  Reconstruction out;
  Report& rep = out.report;

  // 1. Parts (Algorithm 1).
  const std::vector<Part> parts = split_parts(g, o.weld_tolerance);
  if (parts.empty())
    throw HierarchyError("the source geometry has no triangles (" + std::to_string(g.primitives.size()) +
                         " primitives)");
  rep.parts = parts.size();

  // 2. Branch or leaf.
  std::vector<PartClass> cls = classify_parts(parts, g, o.classify);
  const auto is_branch = [](const PartClass& c) { return c.kind == PartKind::kBranch; };
  if (o.classify.mode == ClassifyMode::kAuto && std::none_of(cls.begin(), cls.end(), is_branch)) {
    // Names or materials called every part a leaf: a tree has bark, so let the geometry decide.
    ClassifyOptions geometry = o.classify;
    geometry.mode = ClassifyMode::kGeometry;
    cls = classify_parts(parts, g, geometry);
    rep.classify_fallback = true;
  }
  std::vector<std::size_t> branch_parts, leaf_parts;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (cls[i].kind == PartKind::kBranch) branch_parts.push_back(i);
    if (cls[i].kind == PartKind::kLeaf) leaf_parts.push_back(i);
  }
  rep.branch_parts = branch_parts.size();
  rep.leaf_parts = leaf_parts.size();
  rep.skipped_parts = parts.size() - branch_parts.size() - leaf_parts.size();
  if (branch_parts.empty())
    throw HierarchyError("no branch part among the " + std::to_string(parts.size()) + " parts (" +
                         std::to_string(leaf_parts.size()) + " leaves, " + std::to_string(rep.skipped_parts) +
                         " skipped): nothing to fit a skeleton to");

  // 3. Significant points.
  std::vector<BranchBase> bases;
  std::vector<BranchNode> nodes;
  for (std::size_t i : branch_parts) {
    bases.push_back(branch_base(parts[i]));
    nodes.push_back({&parts[i], bases.back().point, cls[i].level});
  }
  std::vector<Vec3> leaf_points;
  for (std::size_t i : leaf_parts) {
    bool fell_back = false;
    leaf_points.push_back(leaf_point(parts[i], o.leaf_point, &fell_back));
    rep.leaves_without_uvs += fell_back ? 1 : 0;
  }

  // 4. Hierarchy (Algorithm 2, or derived levels without names).
  const Hierarchy h = connect_parts(nodes, leaf_points, o.tolerance);
  rep.levels_from_names = h.levels_from_names;
  rep.leaves_below_top = h.leaves_below_top;
  if (std::none_of(h.level.begin(), h.level.end(), [](std::int32_t l) { return l == 0; }))
    throw HierarchyError("no trunk: no branch part is named br0* (" + std::to_string(branch_parts.size()) +
                         " branch parts)");

  // 5. Skeletons, in level order (parents before children), then the leaves.
  std::vector<std::size_t> order;
  for (std::size_t b = 0; b < nodes.size(); ++b)
    if (h.level[b] >= 0) order.push_back(b);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return h.level[a] < h.level[b]; });
  std::vector<std::int32_t> out_index(nodes.size(), -1);
  tree::Tree& t = out.tree;
  t.name = in.name;
  t.source = in.source;
  for (std::size_t b : order) {
    const SkeletonFit fit = fit_skeleton(parts[branch_parts[b]], bases[b], o.fit);
    tree::Branch br;
    br.level = static_cast<std::uint32_t>(h.level[b]);
    br.nodes = fit.nodes;
    if (h.parent[b] >= 0) {
      br.parent = out_index[static_cast<std::size_t>(h.parent[b])];
      const auto at = closest_on(t.branches[static_cast<std::size_t>(br.parent)].nodes, bases[b].point);
      br.parent_node = at.first;
      br.parent_t = at.second;
    }
    out_index[b] = static_cast<std::int32_t>(t.branches.size());
    if (rep.branches_by_level.size() <= br.level) rep.branches_by_level.resize(br.level + 1, 0);
    ++rep.branches_by_level[br.level];
    rep.branches.push_back({branch_parts[b], br.parent, br.level, br.nodes.size(), br.nodes.front().radius,
                            fit.rms_residual, fit.axis_fallback});
    t.branches.push_back(std::move(br));
  }
  std::vector<bool> kept(parts.size(), false);
  for (std::size_t b : order) kept[branch_parts[b]] = true;
  for (std::size_t l = 0; l < leaf_parts.size(); ++l) {
    if (h.leaf_branch[l] < 0) continue;
    const auto branch = static_cast<std::uint32_t>(out_index[static_cast<std::size_t>(h.leaf_branch[l])]);
    tree::Leaf leaf = fit_leaf(parts[leaf_parts[l]], leaf_points[l], o.leaf_point, t.branches[branch].nodes);
    leaf.branch = branch;
    t.leaves.push_back(leaf);
    kept[leaf_parts[l]] = true;
  }
  rep.leaves = t.leaves.size();
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (kept[i]) continue;
    const char* kind = cls[i].kind == PartKind::kBranch ? "branch"
                       : cls[i].kind == PartKind::kLeaf ? "leaf"
                                                        : "skipped";
    rep.left_out.push_back({i, parts[i].primitive, kind, parts[i].triangles.size(), diagonal(parts[i])});
  }

  // Materials: the file's colours; its textures are wired by the import (kept as it set them).
  t.materials = in.materials;
  t.materials.cell_coverage.clear();
  t.materials.bark_color = mean_color(parts, cls, PartKind::kBranch, g);
  t.materials.leaf_color = mean_color(parts, cls, PartKind::kLeaf, g);
  t.materials.leaf_kind = tree::LeafKind::kTwigCards;
  t.materials.atlas_columns = 1;
  t.materials.atlas_rows = 1;
  return out;
}

}  // namespace sylva::hierarchy
