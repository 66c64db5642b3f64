// Invariant checks for the tree model (tree.h states them).
#include "libs/tree/tree.h"

#include <cmath>
#include <string>

namespace sylva::tree {

namespace {

bool unit(Vec3f v) { return std::abs(length(to_double(v)) - 1.0) <= 1e-3; }

// The first `max` problems found; later ones are dropped.
struct Problems {
  std::vector<std::string> list;
  std::size_t max;
  void fail(std::string msg) {
    if (list.size() < max) list.push_back(std::move(msg));
  }
  bool full() const { return list.size() >= max; }
};

void check_materials(const Tree& tree, Problems& e) {
  const Materials& m = tree.materials;
  auto text = [&](const std::string& value, const char* what) {
    if (value.size() > kMaxTextBytes)
      e.fail(std::string(what) + " is " + std::to_string(value.size()) + " bytes, at most " +
             std::to_string(kMaxTextBytes) + " are stored");
  };
  text(tree.name, "the tree name");
  text(m.bark_texture, "materials: the bark texture name");
  text(m.leaf_texture, "materials: the leaf texture name");
  if (m.atlas_columns < 1 || m.atlas_columns > 16 || m.atlas_rows < 1 || m.atlas_rows > 16)
    e.fail("materials: the leaf atlas must have 1..16 columns and rows, has " +
           std::to_string(m.atlas_columns) + "x" + std::to_string(m.atlas_rows));
  if (!m.cell_coverage.empty() && m.cell_coverage.size() != m.atlas_cells())
    e.fail("materials: " + std::to_string(m.cell_coverage.size()) + " cell coverages for " +
           std::to_string(m.atlas_cells()) + " atlas cells");
  for (std::size_t i = 0; i < m.cell_coverage.size(); ++i)
    if (!(m.cell_coverage[i] >= 0 && m.cell_coverage[i] <= 1))
      e.fail("materials: cell coverage " + std::to_string(i) + " must be in [0, 1]");
  if (static_cast<unsigned>(m.leaf_kind) > 2) e.fail("materials: unknown leaf kind");
  auto in01 = [](float v) { return v >= 0 && v <= 1; };
  // Linear RGB factors (glTF baseColorFactor, which must lie in [0, 1]); NaN fails too.
  if (!in01(m.bark_color.r) || !in01(m.bark_color.g) || !in01(m.bark_color.b))
    e.fail("materials: bark colour components must be in [0, 1]");
  if (!in01(m.leaf_color.r) || !in01(m.leaf_color.g) || !in01(m.leaf_color.b))
    e.fail("materials: leaf colour components must be in [0, 1]");
  if (!in01(m.bark_tint.r) || !in01(m.bark_tint.g) || !in01(m.bark_tint.b))
    e.fail("materials: bark tint components must be in [0, 1]");
  if (!std::isfinite(m.bark_tint_from_m) || !std::isfinite(m.bark_tint_to_m) ||
      m.bark_tint_from_m > m.bark_tint_to_m)
    e.fail("materials: bark tint heights must be finite with from <= to");
}

// Branch `i`: its nodes, and its attachment to a parent listed before it.
void check_branch(const Tree& tree, std::size_t i, Problems& e) {
  const Branch& b = tree.branches[i];
  const std::string where = "branch " + std::to_string(i) + ": ";
  if (b.nodes.size() < 2)
    e.fail(where + "has " + std::to_string(b.nodes.size()) + " nodes, needs at least 2");
  for (std::size_t k = 0; k < b.nodes.size(); ++k) {
    const Node& n = b.nodes[k];
    if (!is_finite(n.position)) e.fail(where + "node " + std::to_string(k) + ": position is not finite");
    if (!std::isfinite(n.radius) || n.radius < 0)
      e.fail(where + "node " + std::to_string(k) + ": radius must be finite and >= 0");
  }
  if (b.parent < 0) {
    if (b.parent != -1) e.fail(where + "parent " + std::to_string(b.parent) + " is invalid");
    if (b.level != 0) e.fail(where + "a root must have level 0, has " + std::to_string(b.level));
    if (b.parent_node != 0 || b.parent_t != 0) e.fail(where + "a root has no parent node");
    return;
  }
  if (static_cast<std::size_t>(b.parent) >= i) {
    e.fail(where + "parent " + std::to_string(b.parent) + " is not before it");
    return;
  }
  const Branch& p = tree.branches[static_cast<std::size_t>(b.parent)];
  if (b.parent_node >= p.nodes.size())
    e.fail(where + "parent node " + std::to_string(b.parent_node) + " is out of range (parent has " +
           std::to_string(p.nodes.size()) + " nodes)");
  if (!(b.parent_t >= 0 && b.parent_t <= 1)) e.fail(where + "parent_t must be in [0, 1]");
  if (b.parent_t != 0 && b.parent_node + 1 >= p.nodes.size())
    e.fail(where + "parent_t must be 0 at the parent's last node");
  if (b.level != p.level && b.level != p.level + 1)
    e.fail(where + "level " + std::to_string(b.level) + " must be the parent's level " +
           std::to_string(p.level) + " or one more");
}

void check_leaf(const Tree& tree, std::size_t i, Problems& e) {
  const Leaf& l = tree.leaves[i];
  const std::string where = "leaf " + std::to_string(i) + ": ";
  if (l.branch >= tree.branches.size())
    e.fail(where + "branch " + std::to_string(l.branch) + " does not exist");
  if (!is_finite(l.position) || !is_finite(l.direction) || !is_finite(l.normal))
    e.fail(where + "position or frame is not finite");
  else if (!unit(l.direction) || !unit(l.normal) ||
           std::abs(dot(to_double(l.direction), to_double(l.normal))) > 1e-3)
    e.fail(where + "direction and normal must be orthogonal unit vectors");
  if (!(l.length > 0) || !(l.width > 0) || !std::isfinite(l.length) || !std::isfinite(l.width))
    e.fail(where + "length and width must be finite and > 0");
  if (l.variant >= tree.materials.atlas_cells())
    e.fail(where + "variant " + std::to_string(l.variant) + " is not a cell of the " +
           std::to_string(tree.materials.atlas_columns) + "x" + std::to_string(tree.materials.atlas_rows) +
           " leaf atlas");
}

void check_needle(const Tree& tree, std::size_t i, Problems& e) {
  const Needle& n = tree.needles[i];
  const std::string where = "needle " + std::to_string(i) + ": ";
  if (n.branch >= tree.branches.size())
    e.fail(where + "branch " + std::to_string(n.branch) + " does not exist");
  if (!is_finite(n.base) || !is_finite(n.tip)) e.fail(where + "base or tip is not finite");
  if (!(n.radius > 0) || !std::isfinite(n.radius)) e.fail(where + "radius must be finite and > 0");
}

}  // namespace

std::vector<std::string> validate_tree(const Tree& tree, std::size_t max_errors) {
  Problems e{{}, max_errors};
  check_materials(tree, e);
  for (std::size_t i = 0; i < tree.branches.size() && !e.full(); ++i) check_branch(tree, i, e);
  for (std::size_t i = 0; i < tree.leaves.size() && !e.full(); ++i) check_leaf(tree, i, e);
  for (std::size_t i = 0; i < tree.needles.size() && !e.full(); ++i) check_needle(tree, i, e);
  // The imported mesh's messages start with "source ..." and are kept as they are.
  if (!e.full())
    for (std::string& m : validate_source_geometry(tree.source, e.max - e.list.size())) e.fail(std::move(m));
  return std::move(e.list);
}

Vec3 attachment_point(const Tree& tree, const Branch& b) {
  const Branch& p = tree.branches[static_cast<std::size_t>(b.parent)];
  const Vec3 a = p.nodes[b.parent_node].position;
  if (b.parent_t == 0) return a;
  const Vec3 c = p.nodes[b.parent_node + 1].position;
  return a + (c - a) * b.parent_t;
}

}  // namespace sylva::tree
