// Cylinder table -> tree skeleton; the rules are stated in qsm_to_tree.h. Phases:
//   1. frame conversion (Z up -> Y up, scale, recentring);
//   2. child lists and the continuation child of every cylinder;
//   3. breadth-first walk: each queued cylinder starts a branch that follows continuations;
//      its nodes, radii and level are set, and its other children are queued with their
//      attachment point.
#include "stages/import/qsm_to_tree.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "stages/import/import_error.h"
#include "stages/import/text_scan.h"
#include "stages/import/value_limits.h"

namespace sylva::import {

namespace {

using tree::Vec3;

struct Pending {
  std::int32_t first = -1;   // cylinder that starts the branch
  std::int32_t parent = -1;  // parent branch index
  std::uint32_t parent_node = 0;
  double parent_t = 0;
};

// The point of segment a -> c nearest to q, as (node, t) with the tree model's convention:
// t in (0, 1) on the segment, the end node itself (t = 0) at either end.
void attach(const tree::Branch& b, std::uint32_t s, std::uint32_t e, Vec3 q, Pending& out) {
  out.parent_node = s;
  out.parent_t = 0;
  if (s == e) return;
  const Vec3 a = b.nodes[s].position, d = b.nodes[e].position - a;
  const double dd = tree::dot(d, d);
  const double t = dd > 0 ? tree::dot(q - a, d) / dd : 0;
  constexpr double kSnap = 1e-9;  // SimpleForest children start exactly at the parent's end
  if (t >= 1 - kSnap)
    out.parent_node = e;
  else if (t > kSnap)
    out.parent_t = t;
}

// Phase 1: frame conversion: (x, y, z)_qsm -> (x, z, -y), scaled, relative to the root's start.
class Placement {
 public:
  Placement(const CylinderTable& table, std::string_view source, const QsmToTreeOptions& options)
      : source_(source), options_(options) {
    origin_ =
        options.recenter ? convert(table.cylinders[static_cast<std::size_t>(table.root)].start) : Vec3{};
  }

  Vec3 place(Vec3 p) const { return convert(p) - origin_; }

  // Finite input can still overflow (1e308 scaled or recentred): report the row.
  Vec3 place_checked(const Cylinder& c, Vec3 p) const {
    const Vec3 q = place(p);
    if (!tree::is_finite(q))
      throw ImportError(
          source_, c.line,
          "cylinder " + std::to_string(c.id) + ": coordinates overflow after scaling and recentring");
    if (std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)}) > kMaxCoordinateM)
      throw ImportError(source_, c.line,
                        "cylinder " + std::to_string(c.id) + ": a point lies " +
                            text::format_real(std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)})) +
                            " m from the " + (options_.recenter ? "root" : "origin") + " (at most " +
                            std::to_string(static_cast<long long>(kMaxCoordinateM)) +
                            " m): check the scale parameter" +
                            (options_.recenter ? "" : " or set recenter: true"));
    return q;
  }

 private:
  Vec3 convert(Vec3 p) const {
    const Vec3 q = options_.up == UpAxis::kZ ? Vec3{p.x, p.z, -p.y} : p;
    return q * options_.scale;
  }

  std::string_view source_;
  const QsmToTreeOptions& options_;
  Vec3 origin_;
};

// Phase 2: children (CSR, file order) and the continuation of every cylinder.
struct Topology {
  std::vector<std::int32_t> first_child;  // cylinder i's children: children[first_child[i] .. [i + 1])
  std::vector<std::int32_t> children;
  std::vector<std::int32_t> next;  // the child that continues the cylinder's branch, -1 at a tip
};

Topology topology(const CylinderTable& table) {
  const auto& cyl = table.cylinders;
  const std::size_t n = cyl.size();
  Topology t{std::vector<std::int32_t>(n + 1, 0), std::vector<std::int32_t>(n),
             std::vector<std::int32_t>(n, -1)};
  for (const Cylinder& c : cyl)
    if (c.parent >= 0) ++t.first_child[static_cast<std::size_t>(c.parent) + 1];
  for (std::size_t i = 0; i < n; ++i) t.first_child[i + 1] += t.first_child[i];
  {
    std::vector<std::int32_t> fill(t.first_child.begin(), t.first_child.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      if (cyl[i].parent >= 0)
        t.children[static_cast<std::size_t>(fill[static_cast<std::size_t>(cyl[i].parent)]++)] =
            static_cast<std::int32_t>(i);
  }
  auto at = [&](std::int32_t i) -> const Cylinder& { return cyl[static_cast<std::size_t>(i)]; };
  for (std::size_t p = 0; p < n; ++p) {
    std::int32_t best = -1;
    for (auto k = t.first_child[p]; k < t.first_child[p + 1]; ++k) {
      const std::int32_t c = t.children[static_cast<std::size_t>(k)];
      if (table.has_branch && at(c).branch != cyl[p].branch) continue;
      if (table.has_order && at(c).order != cyl[p].order) continue;
      if (best < 0 || at(c).radius > at(best).radius) best = c;
    }
    t.next[p] = best;
  }
  return t;
}

// Phase 3: the level of a branch starting at cylinder `first` on a branch of `parent_level`.
std::uint32_t branch_level(const CylinderTable& table, const Cylinder& first, std::uint32_t parent_level,
                           std::string_view source) {
  if (!table.has_order) return parent_level + 1;
  const std::int64_t root_order = table.cylinders[static_cast<std::size_t>(table.root)].order;
  const std::int64_t level = first.order - root_order;
  if (level != parent_level && level != parent_level + 1)
    throw ImportError(source, first.line,
                      "cylinder " + std::to_string(first.id) + " starts a branch of order " +
                          std::to_string(first.order) + " on a branch of order " +
                          std::to_string(parent_level + root_order) +
                          "; a child branch has its parent's order or one more");
  return static_cast<std::uint32_t>(level);
}

// Phase 3: a branch's nodes along `chain`: the first start, then every end that moves; radii
// averaged per node. Records each cylinder's start and end node.
void add_nodes(const CylinderTable& table, const std::vector<std::int32_t>& chain, const Placement& placement,
               double scale, std::string_view source, tree::Branch& b, std::vector<std::uint32_t>& start_node,
               std::vector<std::uint32_t>& end_node) {
  const auto& cyl = table.cylinders;
  const Cylinder& first = cyl[static_cast<std::size_t>(chain.front())];
  std::vector<double> radius_mean;  // running mean of the cylinders touching each node
  std::vector<int> radius_count;
  auto add_radius = [&](std::size_t node, double r) {
    radius_mean[node] += (r - radius_mean[node]) / ++radius_count[node];
  };
  b.nodes.push_back({placement.place_checked(first, first.start), 0});
  radius_mean.assign(1, 0);
  radius_count.assign(1, 0);
  for (const std::int32_t c : chain) {
    const auto ci = static_cast<std::size_t>(c);
    const Vec3 e = placement.place_checked(cyl[ci], cyl[ci].end);
    const double r = cyl[ci].radius * scale;
    if (!(r > 0) || !std::isfinite(r))
      throw ImportError(source, cyl[ci].line,
                        "cylinder " + std::to_string(cyl[ci].id) + ": radius " +
                            text::format_real(cyl[ci].radius) + " is not representable after scaling");
    if (r > kMaxRadiusM)
      throw ImportError(source, cyl[ci].line,
                        "cylinder " + std::to_string(cyl[ci].id) + ": radius " + text::format_real(r) +
                            " m is larger than " + std::to_string(static_cast<long long>(kMaxRadiusM)) +
                            " m: check the scale parameter");
    start_node[ci] = static_cast<std::uint32_t>(b.nodes.size() - 1);
    if (e != b.nodes.back().position) {
      b.nodes.push_back({e, 0});
      radius_mean.push_back(0);
      radius_count.push_back(0);
      add_radius(start_node[ci], r);
      add_radius(b.nodes.size() - 1, r);
    }
    end_node[ci] = static_cast<std::uint32_t>(b.nodes.size() - 1);
  }
  if (b.nodes.size() < 2)
    throw ImportError(source, first.line,
                      "cylinder " + std::to_string(first.id) +
                          " starts a branch of zero length (every cylinder of it has its end "
                          "at its start)");
  for (std::size_t k = 0; k < b.nodes.size(); ++k) b.nodes[k].radius = radius_mean[k];
}

}  // namespace

tree::Tree qsm_to_tree(const CylinderTable& table, std::string_view source, const QsmToTreeOptions& options) {
  const auto& cyl = table.cylinders;
  const std::size_t n = cyl.size();

  // 1. Frame conversion.
  const Placement placement(table, source, options);

  // 2. Children and continuations.
  const Topology topo = topology(table);

  // 3. Breadth-first walk over branches.
  tree::Tree result;
  result.name = "QSM " + table.variant + ", " + std::to_string(n) + " cylinders";
  std::vector<std::uint32_t> start_node(n, 0), end_node(n, 0);
  std::vector<std::int32_t> chain;
  std::vector<Pending> queue{Pending{table.root, -1, 0, 0}};
  queue.reserve(n);
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const Pending pending = queue[head];
    chain.clear();
    for (std::int32_t c = pending.first; c >= 0; c = topo.next[static_cast<std::size_t>(c)])
      chain.push_back(c);

    tree::Branch b;
    b.parent = pending.parent;
    b.parent_node = pending.parent_node;
    b.parent_t = pending.parent_t;
    if (pending.parent >= 0)
      b.level = branch_level(table, cyl[static_cast<std::size_t>(pending.first)],
                             result.branches[static_cast<std::size_t>(pending.parent)].level, source);
    add_nodes(table, chain, placement, options.scale, source, b, start_node, end_node);

    const auto index = static_cast<std::int32_t>(result.branches.size());
    result.branches.push_back(std::move(b));
    const tree::Branch& placed = result.branches.back();

    // Queue the other children, in the order of their parent cylinders along the branch.
    for (const std::int32_t c : chain) {
      const auto ci = static_cast<std::size_t>(c);
      for (auto k = topo.first_child[ci]; k < topo.first_child[ci + 1]; ++k) {
        const std::int32_t child = topo.children[static_cast<std::size_t>(k)];
        if (child == topo.next[ci]) continue;
        Pending p;
        p.first = child;
        p.parent = index;
        attach(placed, start_node[ci], end_node[ci],
               placement.place(cyl[static_cast<std::size_t>(child)].start), p);
        queue.push_back(p);
      }
    }
  }
  return result;
}

}  // namespace sylva::import
