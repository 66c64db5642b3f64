// Tree -> meshing skeleton (Nystad 2010 §4.3.1 "Creating the DAG", §5.3.1; §4.2.2 for where a
// child hangs; §4.3.3 for v). The steps follow mesh_skeleton.h's numbered list.
#include "stages/mesh/mesh_skeleton.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

namespace sylva::mesh {
namespace {

using tree::Node;

constexpr double kSnap = 0.1;              // parent_t within 10 % of a node snaps to it (Nystad's 10 % rule)
constexpr double kRadiusTolerance = 1e-3;  // relative; "equal" radii (the split case)
constexpr double kMergeFraction = 0.02;    // rings closer than this many corner distances merge
// A flat branch's ring corners stay this far above the first root's base: the generator keeps a
// branch's axis 1.5 r + 2 cm above the ground (docs/stages/generate.md, "Ground"), but a flat
// square section reaches 1.25 x the (clamped) meshing radius below its axis.
constexpr double kFlatGroundClearance = 0.021;
constexpr double kMaxFlatLift = 0.01;  // m

// The tree must pass libs/tree's invariants; MeshError lists every problem found.
void check_meshable(const tree::Tree& tree) {
  if (tree.branches.empty()) throw MeshError("the tree has no branches: nothing to mesh");
  const std::vector<std::string> problems = tree::validate_tree(tree, 3);
  if (!problems.empty()) {
    std::string msg = "invalid tree: " + problems.front();
    for (std::size_t i = 1; i < problems.size(); ++i) msg += "; " + problems[i];
    throw MeshError(msg);
  }
}

// Step 1: a branch is meshed unless `omit` names it or it lies above `max_level`.
bool included(const tree::Tree& tree, const tree::Branch& b, const SkeletonOptions& options) {
  const std::size_t i = static_cast<std::size_t>(&b - tree.branches.data());
  if (i < options.omit.size() && options.omit[i]) return false;
  return options.max_level < 0 || b.level <= static_cast<std::uint32_t>(options.max_level);
}

// Where a child hangs on its parent's original polyline: node k, plus t for a virtual ring.
struct Hang {
  std::uint32_t node = 0;
  double t = 0;  // 0: at the node; (kSnap, 1 - kSnap): virtual ring after node `node`
  friend bool operator<(const Hang& a, const Hang& b) {
    return a.node != b.node ? a.node < b.node : a.t < b.t;
  }
  friend bool operator==(const Hang& a, const Hang& b) = default;
};

Hang hang_of(const tree::Branch& child, const tree::Branch& parent) {
  const std::uint32_t k = child.parent_node;
  const double t = child.parent_t;
  if (t <= kSnap) return {k, 0};
  if (t >= 1 - kSnap && k + 1 < parent.nodes.size()) return {k + 1, 0};
  return {k, t};
}

Node lerp(const Node& a, const Node& b, double t) {
  return {a.position + (b.position - a.position) * t, a.radius + (b.radius - a.radius) * t};
}

// Working state of one tree branch.
struct Work {
  std::int32_t skel = -1;  // skeleton index, -1 = not meshed
  bool dropped = false;    // inside its parent: children re-attach to `drop_parent`
  std::int32_t drop_parent = -1;
  std::uint32_t drop_ring = 0;
  std::vector<Hang> inserts;                 // virtual rings requested by children
  std::vector<std::pair<Hang, bool>> hangs;  // every meshed child: where, and whether it sits
                                             // on a box side (thinner than the continuation)
  std::vector<std::uint32_t> node_ring;      // original node -> ring index with virtual rings
  std::vector<std::uint32_t> collapsed;      // that index -> ring index after junction collapse
  std::uint32_t ring_offset = 0;             // leading rings removed by the clearance rule
};

// Steps 1.-2.: counts the meshed branches and tells each meshed child's parent where the child
// hangs (a virtual ring when mid-segment) and whether it sits on a side of the joint box.
void note_children(const tree::Tree& tree, const SkeletonOptions& options, std::vector<Work>& work,
                   SkeletonStats& stats) {
  for (std::size_t i = 0; i < tree.branches.size(); ++i) {
    const tree::Branch& b = tree.branches[i];
    if (!included(tree, b, options)) continue;
    ++stats.branches_in;
    if (b.parent < 0) continue;
    const tree::Branch& p = tree.branches[static_cast<std::size_t>(b.parent)];
    const Hang h = hang_of(b, p);
    Work& pw = work[static_cast<std::size_t>(b.parent)];
    if (h.t > 0) pw.inserts.push_back(h);
    const bool side = h.node + 1 < p.nodes.size() &&
                      b.nodes[0].radius < p.nodes[h.node + 1].radius * (1 - kRadiusTolerance);
    pw.hangs.emplace_back(h, side);
  }
}

// Ring index (virtual rings included, before the junction collapse) of a hang on `w`'s branch.
std::uint32_t ring_index(const Work& w, const Hang& h) {
  std::uint32_t ring = w.node_ring[h.node];
  if (h.t > 0) {
    const auto it = std::lower_bound(w.inserts.begin(), w.inserts.end(), h);
    ring += 1 + static_cast<std::uint32_t>(
                    it - std::lower_bound(w.inserts.begin(), w.inserts.end(), Hang{h.node, 0}));
  }
  return ring;
}

// Where a meshed branch hangs in the skeleton.
struct Attachment {
  std::int32_t parent = -1;  // skeleton branch, -1 for a root
  std::uint32_t parent_ring = 0;
};

// Where `b` hangs in the skeleton (a dropped parent hands its own attachment down). std::nullopt
// when the parent is not meshed: that cannot happen for a valid tree; it keeps the mesher safe.
std::optional<Attachment> attachment_of(const tree::Tree& tree, const std::vector<Work>& work,
                                        const tree::Branch& b) {
  Attachment at;
  if (b.parent < 0) return at;
  const Work& pw = work[static_cast<std::size_t>(b.parent)];
  if (pw.dropped) {
    at.parent = pw.drop_parent;
    at.parent_ring = pw.drop_ring;
  } else {
    at.parent = pw.skel;
    const std::uint32_t ring =
        pw.collapsed[ring_index(pw, hang_of(b, tree.branches[static_cast<std::size_t>(b.parent)]))];
    at.parent_ring = ring >= pw.ring_offset ? ring - pw.ring_offset : 0;
  }
  if (at.parent < 0) return std::nullopt;
  return at;
}

// Step 2: the branch's nodes with the virtual rings its children asked for, in order along the
// branch; fills w.node_ring.
std::vector<Node> with_virtual_rings(const tree::Branch& b, Work& w, SkeletonStats& stats) {
  std::sort(w.inserts.begin(), w.inserts.end());
  w.inserts.erase(std::unique(w.inserts.begin(), w.inserts.end()), w.inserts.end());
  std::vector<Node> nodes;
  nodes.reserve(b.nodes.size() + w.inserts.size());
  w.node_ring.resize(b.nodes.size());
  std::size_t next_insert = 0;
  for (std::uint32_t j = 0; j < b.nodes.size(); ++j) {
    w.node_ring[j] = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back(b.nodes[j]);
    while (next_insert < w.inserts.size() && w.inserts[next_insert].node == j) {
      nodes.push_back(lerp(b.nodes[j], b.nodes[j + 1], w.inserts[next_insert].t));
      ++stats.virtual_rings;
      ++next_insert;
    }
  }
  return nodes;
}

// Step 3: junction collapse and ring merging over `nodes`; fills w.collapsed.
void collapse_junctions(std::vector<Node>& nodes, Work& w, double k, double min_r, SkeletonStats& stats) {
  // A ring whose children all sit on box sides is the attachment point between the generator's
  // prepended and appended nodes (Nystad §4.2.2); the children hang from the ring before it
  // instead, so their box spans prepended -> appended, centred on them. Not when the ring before
  // has children of its own (its box is taken).
  std::vector<char> has(nodes.size(), 0), all_side(nodes.size(), 1);
  for (const auto& [h, side] : w.hangs) {
    const std::uint32_t r = ring_index(w, h);
    has[r] = 1;
    if (!side) all_side[r] = 0;
  }
  w.collapsed.assign(nodes.size(), 0);
  std::vector<Node> kept;
  kept.reserve(nodes.size());
  bool previous_has = false;
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    if (j >= 1) {
      // A ring (almost) on top of the previous one — the generator's intermediate nodes next to a
      // tapered tip lie microns apart — is merged into it: such rings only make degenerate quads.
      // The last ring replaces the one before it instead, so the tip stays.
      const double tiny = kMergeFraction * k * std::max(nodes[j].radius, min_r);
      if (tree::length(nodes[j].position - kept.back().position) < tiny) {
        ++stats.merged_rings;
        if (j + 1 < nodes.size() || kept.size() < 2) {
          if (j + 1 == nodes.size()) {
            // A two-ring branch of (almost) zero length: keep both rings.
            w.collapsed[j] = static_cast<std::uint32_t>(kept.size());
            kept.push_back(nodes[j]);
            continue;
          }
          w.collapsed[j] = static_cast<std::uint32_t>(kept.size() - 1);
          previous_has = previous_has || has[j];
          continue;
        }
        kept.back() = nodes[j];
        w.collapsed[j] = static_cast<std::uint32_t>(kept.size() - 1);
        previous_has = previous_has || has[j];
        continue;
      }
    }
    if (j >= 1 && j + 1 < nodes.size() && has[j] && all_side[j] && !previous_has) {
      w.collapsed[j] = static_cast<std::uint32_t>(kept.size() - 1);
      previous_has = true;
      ++stats.collapsed_junctions;
      continue;
    }
    w.collapsed[j] = static_cast<std::uint32_t>(kept.size());
    kept.push_back(nodes[j]);
    previous_has = has[j];
  }
  nodes = std::move(kept);
}

// Step 3b: which of `nodes` stay when rings without children are thinned (mesh_skeleton.h,
// ring_tolerance). Greedy along the branch: a candidate is left out when the segment from the
// last kept ring to the ring after the candidate passes within the tolerance of the candidate and
// of every ring left out since that kept ring. At most kMaxRun rings in a row are left out, which
// bounds the work per ring. Returns a keep flag per node.
constexpr std::size_t kMaxRun = 32;
constexpr double kRadiusFraction = 0.02;  // radius error allowed on thick branches (relative)
constexpr double kThinRadius = 0.03;      // ... and on thin ones, as a fraction of the tolerance

std::vector<char> thin_rings(const std::vector<Node>& nodes, const std::vector<char>& has, double tol) {
  const std::size_t n = nodes.size();
  std::vector<char> keep(n, 1);
  if (!(tol > 0) || n < 3) return keep;
  auto protected_ring = [&](std::size_t j) {
    return j == 0 || j + 1 == n || has[j] || has[j - 1] || has[j + 1];
  };
  auto fits = [&](std::size_t a, std::size_t b, std::size_t j) {
    const Vec3 d = nodes[b].position - nodes[a].position;
    const double len2 = tree::dot(d, d);
    const double t =
        len2 > 0 ? std::clamp(tree::dot(nodes[j].position - nodes[a].position, d) / len2, 0.0, 1.0) : 0;
    const Vec3 p = nodes[a].position + d * t;
    if (tree::length(nodes[j].position - p) > tol) return false;
    const double r = nodes[a].radius + (nodes[b].radius - nodes[a].radius) * t;
    return std::abs(r - nodes[j].radius) <= std::max(kRadiusFraction * nodes[j].radius, kThinRadius * tol);
  };
  std::size_t anchor = 0;
  for (std::size_t j = 1; j + 1 < n; ++j) {
    bool drop = !protected_ring(j) && j - anchor <= kMaxRun;
    for (std::size_t i = anchor + 1; drop && i <= j; ++i) drop = fits(anchor, j + 1, i);
    if (drop) {
      keep[j] = 0;
    } else {
      anchor = j;
    }
  }
  return keep;
}

// Step 3b applied: the rings thin_rings leaves out are removed from `nodes` and w.collapsed maps
// onto the rings that stay.
void thin_branch_rings(std::vector<Node>& nodes, Work& w, double tolerance, SkeletonStats& stats) {
  std::vector<char> has_kept(nodes.size(), 0);
  for (const auto& hs : w.hangs) has_kept[w.collapsed[ring_index(w, hs.first)]] = 1;
  const std::vector<char> keep = thin_rings(nodes, has_kept, tolerance);
  std::vector<std::uint32_t> remap(nodes.size(), 0);
  std::vector<Node> thinned;
  thinned.reserve(nodes.size());
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    if (keep[j])
      thinned.push_back(nodes[j]);
    else
      ++stats.thinned_rings;
    remap[j] = static_cast<std::uint32_t>(thinned.size() - 1);
  }
  for (std::uint32_t& c : w.collapsed) c = remap[c];
  nodes = std::move(thinned);
}

// Step 3 (end): radii below min_r are raised to it. Returns the tree's radii (the rings'
// source_radius), taken before.
std::vector<double> clamp_radii(std::vector<Node>& nodes, double min_r, SkeletonStats& stats) {
  std::vector<double> source_radius;
  source_radius.reserve(nodes.size());
  for (const Node& nd : nodes) source_radius.push_back(nd.radius);
  for (Node& nd : nodes)
    if (!(nd.radius >= min_r)) {
      nd.radius = min_r;
      ++stats.clamped_radii;
    }
  return source_radius;
}

// Step 4: joint clearance for a lateral that will sit on a side face of its parent's joint box
// (smaller than the parent's continuation at that ring). Returns false when the branch lies
// entirely inside its parent (4b): it is then not meshed and `w` hands its attachment down.
bool clear_joint(std::vector<Node>& nodes, std::vector<double>& source_radius, Work& w, const Attachment& at,
                 const std::vector<SkeletonBranch>& branches, double k, SkeletonStats& stats) {
  const SkeletonBranch& pb = branches[static_cast<std::size_t>(at.parent)];
  const Ring& pr = pb.rings[at.parent_ring];
  const bool side = at.parent_ring + 1 < pb.rings.size() &&
                    source_radius[0] < pb.rings[at.parent_ring + 1].source_radius * (1 - kRadiusTolerance);
  if (!side) return true;
  // The box's side faces look along +-n and +-b of the ring's frame (its corners sit at
  // 45 degrees); a ring must lie in front of the face it will join.
  const double face = std::numbers::sqrt2 / 2 * k * pr.radius;
  const Vec3 normals[4] = {pr.frame.n, pr.frame.b, -pr.frame.n, -pr.frame.b};
  auto facing = [&](const Node& nd) {
    const Vec3 d = nd.position - pr.center;
    std::size_t best = 0;
    for (std::size_t f = 1; f < 4; ++f)
      if (tree::dot(normals[f], d) > tree::dot(normals[best], d)) best = f;
    return normals[best];
  };
  auto required = [&](const Node& nd) { return face + 0.25 * k * nd.radius; };
  auto clearance = [&](const Node& nd) {
    return tree::dot(nd.position - pr.center, facing(nd)) - required(nd);
  };
  auto inside = [&](const Node& nd) { return clearance(nd) < 0; };
  std::size_t first = 0;
  while (first + 1 < nodes.size() && inside(nodes[first + 1])) ++first;
  if (first + 1 == nodes.size() && inside(nodes[first])) {
    // 4b. Entirely inside the parent: not meshed; its children hang from here instead.
    w.dropped = true;
    w.drop_parent = at.parent;
    w.drop_ring = at.parent_ring;
    ++stats.dropped_branches;
    stats.dropped_rings += nodes.size();
    return false;
  }
  if (first > 0) {
    nodes.erase(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(first));
    source_radius.erase(source_radius.begin(), source_radius.begin() + static_cast<std::ptrdiff_t>(first));
    w.ring_offset = static_cast<std::uint32_t>(first);
    stats.dropped_rings += first;
  }
  if (inside(nodes[0])) {
    if (nodes.size() > 1) {
      // Cut the child where its first segment leaves the box face (the clearance is
      // linear along the segment for a fixed face): the ring keeps the child's direction.
      const double c0 = clearance(nodes[0]),
                   c1 = tree::dot(nodes[1].position - pr.center, facing(nodes[0])) - required(nodes[1]);
      const double t = c1 > c0 ? std::clamp(-c0 / (c1 - c0), 0.0, 1.0) : 1.0;
      nodes[0] = lerp(nodes[0], nodes[1], t);
      source_radius[0] += (source_radius[1] - source_radius[0]) * t;
      // Cut right next to the second ring: drop the first instead (no degenerate quads).
      if (tree::length(nodes[1].position - nodes[0].position) < kMergeFraction * k * nodes[1].radius) {
        nodes.erase(nodes.begin());
        source_radius.erase(source_radius.begin());
        ++w.ring_offset;
        ++stats.dropped_rings;
      }
    }
    if (inside(nodes[0])) nodes[0].position += facing(nodes[0]) * (-clearance(nodes[0]));
    ++stats.pushed_rings;
  }
  return true;
}

// Step 5: frames of the rings. Zhang et al.'s rule (eq. A1, as libs/tree/frames.h) propagates the
// normal, but each tangent is the chord over +-w of arc length around the ring (w = the ring's
// corner distance) rather than the bisector of the two adjacent segments: rings closer together
// than their size then stay nearly parallel, so a bend at a short segment (the generator's
// prepended and appended nodes sit one child radius from a junction where the natural rules turn
// the branch) does not make neighbouring rings cross and fold the tube.
std::vector<Frame> ring_frames(const std::vector<Node>& nodes, double corner_scale, Vec3 initial_normal,
                               Vec3 fallback_t) {
  const std::size_t n = nodes.size();
  std::vector<double> s(n, 0);
  for (std::size_t i = 1; i < n; ++i)
    s[i] = s[i - 1] + tree::length(nodes[i].position - nodes[i - 1].position);
  auto at = [&](double x) {
    x = std::clamp(x, 0.0, s.back());
    std::size_t j = static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), x) - s.begin());
    j = std::clamp<std::size_t>(j, 1, n - 1);
    const double len = s[j] - s[j - 1];
    const double t = len > 0 ? (x - s[j - 1]) / len : 0;
    return nodes[j - 1].position + (nodes[j].position - nodes[j - 1].position) * t;
  };
  std::vector<Frame> f(n);
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 t{};
    if (n > 1) {
      const double w = std::max(corner_scale * nodes[i].radius, 1e-9);
      t = at(s[i] + w) - at(s[i] - w);
      // A zero chord (a 180-degree reversal): the nearest non-degenerate segment.
      for (std::size_t d = 0; tree::length(t) == 0 && d < n; ++d) {
        if (i + d + 1 < n) t = nodes[i + d + 1].position - nodes[i + d].position;
        if (tree::length(t) == 0 && i >= d + 1) t = nodes[i - d].position - nodes[i - d - 1].position;
      }
    }
    f[i].t = tree::length(t) > 0 ? tree::normalized(t) : fallback_t;
  }
  // Normals: N_0 from the initial normal, then N_{k+1} = (T_{k+1} x N_k) x T_{k+1} (A1).
  auto perpendicular = [](Vec3 t) {
    const Vec3 a = std::abs(t.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    return tree::normalized(tree::cross(tree::cross(t, a), t));
  };
  Vec3 n0 = initial_normal - f[0].t * tree::dot(initial_normal, f[0].t);
  f[0].n = tree::length(n0) > 1e-9 ? tree::normalized(n0) : perpendicular(f[0].t);
  f[0].b = tree::cross(f[0].t, f[0].n);
  for (std::size_t i = 1; i < n; ++i) {
    const Vec3 b = tree::cross(f[i].t, f[i - 1].n);
    if (tree::length(b) > 1e-9) {
      f[i].b = tree::normalized(b);
      f[i].n = tree::cross(f[i].b, f[i].t);
    } else {
      const Frame g = tree::transport_frame(f[i - 1], f[i].t);
      f[i].n = g.n;
      f[i].b = g.b;
    }
  }
  return f;
}

// Step 5 for a branch: rotation-minimising along the rings, continued from the parent across the
// joint (a root starts from N = +X).
std::vector<Frame> branch_frames(const std::vector<Node>& nodes, const Attachment& at,
                                 const std::vector<SkeletonBranch>& branches, double k) {
  Vec3 initial_normal{1, 0, 0};
  Vec3 fallback_t{0, 1, 0};
  if (at.parent >= 0) {
    const Ring& pr = branches[static_cast<std::size_t>(at.parent)].rings[at.parent_ring];
    fallback_t = nodes.size() > 1 ? nodes[1].position - nodes[0].position : nodes[0].position - pr.center;
    if (tree::length(fallback_t) == 0) fallback_t = pr.frame.t;
    fallback_t = tree::normalized(fallback_t);
    initial_normal = tree::transport_frame(pr.frame, fallback_t).n;
  }
  return ring_frames(nodes, k, initial_normal, fallback_t);
}

// Step 7: a root stands on a horizontal first ring (its base cap lies in the ground plane).
void stand_flat(Frame& f0) {
  f0.t = Vec3{0, 1, 0};
  Vec3 n0 = f0.n - f0.t * tree::dot(f0.n, f0.t);
  if (tree::length(n0) < 1e-9) n0 = Vec3{1, 0, 0};
  f0.n = tree::normalized(n0);
  f0.b = tree::cross(f0.t, f0.n);
}

// Ring radii r^ whose cubic B-spline limit (r^_{k-1} + 4 r^_k + r^_{k+1}) / 6 is the skeleton's
// r_k at every interior ring, the first and last kept (Thomas algorithm; the system is
// diagonally dominant). Clamped to [min_r, 1.5 r_k] so a radius step (a da Vinci junction) cannot
// ring into a negative or bulging radius.
void precompensate(std::vector<Node>& nodes, double min_r) {
  const std::size_t n = nodes.size();
  if (n < 3) return;
  const std::size_t m = n - 2;  // unknowns r^_1 .. r^_{n-2}
  std::vector<double> c(m), d(m);
  for (std::size_t i = 0; i < m; ++i) {
    double rhs = 6 * nodes[i + 1].radius;
    if (i == 0) rhs -= nodes[0].radius;
    if (i + 1 == m) rhs -= nodes[n - 1].radius;
    const double denom = 4 - (i > 0 ? c[i - 1] : 0.0);
    c[i] = 1 / denom;
    d[i] = (rhs - (i > 0 ? d[i - 1] : 0.0)) / denom;
  }
  std::vector<double> x(m);
  for (std::size_t i = m; i-- > 0;) x[i] = d[i] - (i + 1 < m ? c[i] * x[i + 1] : 0.0);
  for (std::size_t i = 0; i < m; ++i)
    nodes[i + 1].radius = std::clamp(x[i], min_r, 1.5 * std::max(nodes[i + 1].radius, min_r));
}

// Step 7 (radii): a smooth branch's radii pre-compensated for Catmull–Clark (when asked); a flat
// one's scaled by rough_scale and lifted clear of the ground plane through `ground_y`.
void shape_radii(std::vector<Node>& nodes, bool smooth, const SkeletonOptions& options, double min_r,
                 double ground_y) {
  if (smooth) {
    if (options.compensate_smoothing) precompensate(nodes, min_r);
    return;
  }
  const double k = options.corner_scale;
  for (Node& nd : nodes) {
    nd.radius *= options.rough_scale;
    const double low = nd.position.y - k * nd.radius - (ground_y + kFlatGroundClearance);
    // Lifted by the few millimetres the square section adds; a real skeleton that goes below
    // the ground (imported trees) is left where it is.
    if (low < 0 && low > -kMaxFlatLift) nd.position.y -= low;
  }
}

// Step 6: v per metre of arc length at radius r; r0 is the first root's base radius.
double v_per_metre(double r0, double r) {
  const double two_pi = 2 * std::numbers::pi;
  return 1.0 / (two_pi * (0.2 * r0 + 0.8 * r));
}

// Step 6: the branch's rings with texture v, continuing the attachment ring's v across the joint.
std::vector<Ring> rings_with_v(const std::vector<Node>& nodes, const std::vector<Frame>& frames,
                               const std::vector<double>& source_radius, const Attachment& at,
                               const std::vector<SkeletonBranch>& branches, double r0) {
  std::vector<Ring> rings(nodes.size());
  double v = 0;
  if (at.parent >= 0) {
    const Ring& pr = branches[static_cast<std::size_t>(at.parent)].rings[at.parent_ring];
    v = pr.v +
        tree::length(nodes[0].position - pr.center) * v_per_metre(r0, 0.5 * (pr.radius + nodes[0].radius));
  }
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    if (j > 0)
      v += tree::length(nodes[j].position - nodes[j - 1].position) *
           v_per_metre(r0, 0.5 * (nodes[j].radius + nodes[j - 1].radius));
    rings[j] = {nodes[j].position, frames[j], nodes[j].radius, source_radius[j], v};
  }
  return rings;
}

// The DAG's child lists: per skeleton branch and ring, the branches growing from it, in order.
void link_children(MeshSkeleton& sk) {
  sk.children.resize(sk.branches.size());
  for (std::size_t i = 0; i < sk.branches.size(); ++i) sk.children[i].resize(sk.branches[i].rings.size());
  for (std::size_t i = 0; i < sk.branches.size(); ++i) {
    const SkeletonBranch& b = sk.branches[i];
    if (b.parent >= 0)
      sk.children[static_cast<std::size_t>(b.parent)][b.parent_ring].push_back(static_cast<std::uint32_t>(i));
  }
}

}  // namespace

std::size_t MeshSkeleton::ring_count() const {
  std::size_t n = 0;
  for (const auto& b : branches) n += b.rings.size();
  return n;
}

MeshSkeleton build_skeleton(const tree::Tree& tree, const SkeletonOptions& options) {
  check_meshable(tree);
  const double min_r = options.min_radius > 0 ? options.min_radius : 1e-6;
  const double k = options.corner_scale;
  MeshSkeleton sk;
  std::vector<Work> work(tree.branches.size());

  // 1.-2. Which branches are meshed, and the virtual rings their children need.
  note_children(tree, options, work, sk.stats);

  const double r0 = std::max(tree.branches[0].nodes[0].radius, min_r);
  const double ground_y = tree.branches[0].nodes[0].position.y;
  sk.v_unit = 2 * std::numbers::pi * r0;

  // Parents come before children in the tree, so each branch finds its parent's rings built.
  for (std::size_t i = 0; i < tree.branches.size(); ++i) {
    const tree::Branch& b = tree.branches[i];
    Work& w = work[i];
    if (!included(tree, b, options)) continue;
    const std::optional<Attachment> at = attachment_of(tree, work, b);
    if (!at) continue;
    // Smooth (subdivided) unless thinner than smooth_min_radius.
    const bool smooth = !(b.nodes[0].radius < options.smooth_min_radius);

    // 2.-3. Nodes with virtual rings, junctions collapsed, rings merged (and thinned), radii clamped.
    std::vector<Node> nodes = with_virtual_rings(b, w, sk.stats);
    collapse_junctions(nodes, w, k, min_r, sk.stats);
    if (!smooth && options.ring_tolerance > 0 && nodes.size() > 2)
      thin_branch_rings(nodes, w, options.ring_tolerance, sk.stats);
    std::vector<double> source_radius = clamp_radii(nodes, min_r, sk.stats);

    // 4. Joint clearance; a branch entirely inside its parent is not meshed.
    if (at->parent >= 0 && !clear_joint(nodes, source_radius, w, *at, sk.branches, k, sk.stats)) continue;

    // 5. Frames; 7. a root stands flat, and the radii are shaped for how the branch is meshed.
    std::vector<Frame> frames = branch_frames(nodes, *at, sk.branches, k);
    if (at->parent < 0 && !frames.empty()) stand_flat(frames[0]);
    shape_radii(nodes, smooth, options, min_r, ground_y);

    // 6. Texture v, and the branch joins the skeleton.
    SkeletonBranch out;
    out.source = static_cast<std::uint32_t>(i);
    out.parent = at->parent;
    out.parent_ring = at->parent_ring;
    out.level = b.level;
    out.clone = tree::is_clone(tree, b);
    out.smooth = smooth;
    out.rings = rings_with_v(nodes, frames, source_radius, *at, sk.branches, r0);
    w.skel = static_cast<std::int32_t>(sk.branches.size());
    sk.branches.push_back(std::move(out));
  }

  link_children(sk);
  return sk;
}

}  // namespace sylva::mesh
