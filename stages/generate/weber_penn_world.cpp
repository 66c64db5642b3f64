// Pass 3 of the Weber & Penn generator: world (weber_penn.cpp gives the outline). Per branch, in
// parent-first order, walk the nodes carrying a frame (direction and side); curve and attraction
// turn it at segment nodes; at junctions the children's frames are taken and then the primary
// deviation (Murray's angle for the primary) turns the rest of the branch — and with it every
// later child — which is exactly the thesis's parent-relative propagation, in one O(nodes) pass.
// Then the foliage, from the same Rng after the branches.
//
// Nystad 2010: §5.2.1 (primary deviation through parent-relative transforms), §3.1 eq. 3.5 (child
// offset). Weber & Penn 1995: curve, attraction up. Ground clearance: docs/stages/generate.md,
// "Ground".
#include <algorithm>
#include <cmath>

#include "stages/generate/foliage_placement.h"
#include "stages/generate/natural_rules.h"
#include "stages/generate/weber_penn_passes.h"

namespace sylva::generate::weber_penn {

namespace {

using tree::Vec3;

constexpr Vec3 kUp{0, 1, 0};

// Rodrigues rotation of v about the unit axis k by angle a.
Vec3 rotate(Vec3 v, Vec3 k, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return v * c + tree::cross(k, v) * s + k * (tree::dot(k, v) * (1 - c));
}

struct Frame {
  Vec3 d;     // unit direction of growth
  Vec3 side;  // unit, orthogonal to d: azimuth 0 and the axis Curve bends about
  void turn(Vec3 axis, double a) {
    d = tree::normalized(rotate(d, axis, a));
    side = rotate(side, axis, a);
    side = tree::normalized(side - d * tree::dot(side, d));  // keep it orthonormal
  }
  // Unit vector orthogonal to d at azimuth phi (0 = side).
  Vec3 out(double phi) const { return side * std::cos(phi) + tree::cross(d, side) * std::sin(phi); }
};

// Where a branch starts: the parent's junction node, the frame it grows along, the parent's radius.
struct Start {
  Vec3 position;
  Frame frame;
  double parent_radius = 0;
};

// Ground: turns f up (about the horizontal axis d x up) just enough that a step of `ds` from
// `pos` ends at least ground_clearance(r) above y = 0. Never turns past the vertical.
void lift(Frame& f, Vec3 pos, double ds, double r) {
  if (!(ds > 0)) return;
  const double want = (ground_clearance(r) - pos.y) / ds;
  if (f.d.y >= want) return;
  const double target = std::asin(std::clamp(want, -1.0, 1.0));
  const double now = std::asin(std::clamp(f.d.y, -1.0, 1.0));
  Vec3 axis = tree::cross(f.d, kUp);
  axis = tree::length(axis) > 1e-9 ? tree::normalized(axis) : f.side;
  f.turn(axis, target - now);
}

Start child_start(const Frame& pre, Vec3 pos, double azimuth, double deviation, double r_parent) {
  const Vec3 o = pre.out(azimuth);
  const Vec3 axis = tree::normalized(tree::cross(pre.d, o));
  Start s;
  s.position = pos;
  s.frame.d = tree::normalized(pre.d * std::cos(deviation) + o * std::sin(deviation));
  s.frame.side = axis;  // Curve bends the child in the plane of its down angle
  s.parent_radius = r_parent;
  return s;
}

// Walks every branch's nodes from its start, parents first, so each junction hands its children
// their start before they are walked.
class Walker {
 public:
  Walker(const Preset& p, const Growth& g, const Structure& s)
      : p_(p),
        stems_(g.stems),
        plans_(g.plans),
        splits_(g.splits),
        curve_(g.curve),
        pull_(g.pull),
        node_begin_(s.node_begin),
        s_(s.s),
        radius_(s.radius),
        info_(s.info) {}

  void world(tree::Tree& t) const {
    t.branches.resize(plans_.size());
    std::vector<Start> start(plans_.size());
    start[0].frame = {kUp, {1, 0, 0}};
    for (std::uint32_t id = 0; id < plans_.size(); ++id) walk_branch(id, start, t.branches[id]);
  }

 private:
  void walk_branch(std::uint32_t id, std::vector<Start>& start, tree::Branch& out) const {
    const BranchPlan& b = plans_[id];
    out.parent = b.parent;
    out.parent_node = b.parent >= 0 ? b.junction : 0;
    out.level = b.level;
    const std::uint32_t n0 = node_begin_[id], n1 = node_begin_[id + 1];
    out.nodes.resize(n1 - n0);
    // The first node: a lateral's first cross-section is (1 + S_s) r_parent from the parent
    // axis (eq. 3.5), measured perpendicular to it; a clone's is its stub.
    Frame f = start[id].frame;
    Vec3 pos = start[id].position;
    const bool grounded = b.parent >= 0;  // every branch but the roots keeps off the ground
    if (b.parent >= 0) {
      const double along =
          b.clone ? s_[n0]
                  : child_offset(b.ratio, start[id].parent_radius) / std::max(std::sin(b.deviation), 0.5);
      lift(f, pos, along, radius_[n0]);
      pos += f.d * along;
    }
    // Hem: the branch may end only after its last junction (its clones stay attached).
    std::uint32_t cut_after = n0;
    if (b.hem > 0)
      for (std::uint32_t k = n0; k < n1; ++k)
        if (info_[k].child_count > 0 || info_[k].split >= 0) cut_after = k;
    for (std::uint32_t k = n0; k < n1; ++k) {
      const NodeInfo& ni = info_[k];
      if (k > n0) {
        if (grounded) lift(f, pos, s_[k] - s_[k - 1], radius_[k]);
        pos += f.d * (s_[k] - s_[k - 1]);
      }
      if (b.hem > 0 && k > cut_after && pos.y < b.hem) {
        end_at_hem(out, n0, k, pos, b.hem);
        break;
      }
      out.nodes[k - n0] = {pos, radius_[k]};
      if (ni.base >= 1 && ni.base < b.nseg) turn_at_segment_node(b, ni.base, f);
      if (ni.child_count > 0 || ni.split >= 0) take_junction(ni, pos, radius_[k], f, start);
      // TrunkUp: a level-0 branch turns back towards the vertical after this node's turns.
      if (b.level == 0 && p_.trunk_up > 0) {
        const Vec3 axis = tree::cross(f.d, kUp);
        const double al = tree::length(axis);
        if (al > 1e-12)
          f.turn(axis / al, p_.trunk_up * std::acos(std::clamp(tree::dot(f.d, kUp), -1.0, 1.0)));
      }
    }
  }

  // The first node below the hem (node k, at `pos`) ends the branch: at the crossing when the
  // previous node is above it (or at that node when the crossing is within a millimetre of it and
  // the branch keeps two nodes without it); at this node when the branch was already below.
  void end_at_hem(tree::Branch& out, std::uint32_t n0, std::uint32_t k, Vec3 pos, double hem) const {
    const tree::Node prev = out.nodes[k - n0 - 1];
    out.nodes[k - n0] = {pos, radius_[k]};
    out.nodes.resize(k - n0 + 1);
    if (prev.position.y >= hem) {
      const double at = (prev.position.y - hem) / (prev.position.y - pos.y);
      if (at * (s_[k] - s_[k - 1]) < 1e-3 && k - 1 > n0)
        out.nodes.pop_back();
      else
        out.nodes.back() = {prev.position + (pos - prev.position) * at,
                            prev.radius + (radius_[k] - prev.radius) * at};
    }
  }

  // Turns at interior segment node `base`: Curve about the side axis, then AttractionUp (and the
  // trunk's split correction) towards the vertical.
  void turn_at_segment_node(const BranchPlan& b, int base, Frame& f) const {
    const int curve_res = stems_[b.stem].curve_res;
    const double attraction = b.level >= 2 ? p_.attraction_up : 0.0;
    const double c = curve_[b.curve_at + static_cast<std::uint32_t>(base)];
    if (c != 0) f.turn(f.side, c);
    double pull = 0;
    if (b.pull_at >= 0) pull = pull_[static_cast<std::size_t>(b.pull_at) + static_cast<std::size_t>(base)];
    const double decl = std::acos(std::clamp(tree::dot(f.d, kUp), -1.0, 1.0));
    double a = attraction * decl / curve_res + pull;
    Vec3 axis = tree::cross(f.d, kUp);
    double al = tree::length(axis);
    if (attraction < 0 && p_.pendulous > 0) {
      // Pendulous: the downward pull grows with the angle from the downward vertical, so a
      // shoot pointing up flops over (straight up: about its side axis).
      const double from_down = (1 - p_.pendulous) * decl + p_.pendulous * (kPi - decl);
      a = attraction * from_down / curve_res + pull;
      if (al <= 1e-9) axis = f.side, al = 1;
    }
    if (a != 0 && al > 1e-9) f.turn(axis / al, a > 0 ? std::min(a, decl) : std::max(a, decl - kPi));
  }

  // Junction at `pos` (radius r): children take the frame as it is (the direction of the segment
  // they grow from); then the primary deviation turns the rest of this branch away from each child.
  void take_junction(const NodeInfo& ni, Vec3 pos, double r, Frame& f, std::vector<Start>& start) const {
    const Frame pre = f;
    if (ni.split >= 0) {
      const SplitPlan& sp = splits_[static_cast<std::size_t>(ni.split)];
      for (int m = 1; m < sp.n; ++m) {
        const std::uint32_t c = sp.first_clone + static_cast<std::uint32_t>(m - 1);
        start[c] = child_start(pre, pos, plans_[c].azimuth, plans_[c].deviation, r);
      }
      const Vec3 o = pre.out(sp.primary_azimuth);
      f.turn(tree::normalized(tree::cross(pre.d, o)), sp.primary_deviation);
    }
    for (std::uint32_t c = ni.first_child; c < ni.first_child + ni.child_count; ++c) {
      start[c] = child_start(pre, pos, plans_[c].azimuth, plans_[c].deviation, r);
      const Vec3 o = pre.out(plans_[c].azimuth);
      f.turn(tree::normalized(tree::cross(pre.d, o)), -plans_[c].primary_angle);
    }
  }

  const Preset& p_;
  const std::vector<Stem>& stems_;
  const std::vector<BranchPlan>& plans_;
  const std::vector<SplitPlan>& splits_;
  const std::vector<double>& curve_;
  const std::vector<double>& pull_;
  const std::vector<std::uint32_t>& node_begin_;
  const std::vector<double>& s_;
  const std::vector<double>& radius_;
  const std::vector<NodeInfo>& info_;
};

}  // namespace

void place_branches(const Preset& p, const Growth& g, const Structure& s, tree::Tree& t) {
  Walker(p, g, s).world(t);
}

// Foliage on the last level (foliage_placement.h), then the bark tint heights.
void add_foliage(const Preset& p, const GenerateOptions& o, const std::vector<std::uint32_t>& last_level,
                 Rng& rng, tree::Tree& t) {
  FoliageSpec spec;
  const bool cards = o.foliage == FoliageMode::kCards;
  spec.mode =
      cards ? FoliageSpec::Mode::kCards
            : (p.foliage == Foliage::kNeedles ? FoliageSpec::Mode::kNeedles : FoliageSpec::Mode::kLeaves);
  spec.target_lai = p.leaf_area_index * o.leaf_density;
  spec.count = p.leaves * o.leaf_density;
  spec.zone = p.foliage_zone;
  spec.leaf_scale = p.leaf_scale;
  spec.leaf_scale_x = p.leaf_scale_x;
  spec.natural_angle = murray_angles_for_ratio(p.tree_shape_exponent, p.leaf.branch_ratio).secondary;
  spec.down_angle_v = p.leaf.down_angle_v * kDeg;
  spec.rotate = p.leaf.rotate * kDeg;
  spec.rotate_v = p.leaf.rotate_v * kDeg;
  spec.card = p.card;
  spec.card.length *= p.card_scale;
  spec.materials = t.materials;
  spec.materials.leaf_kind = !cards                           ? tree::LeafKind::kLeaves
                             : p.foliage == Foliage::kNeedles ? tree::LeafKind::kShootCards
                                                              : tree::LeafKind::kTwigCards;
  spec.materials.atlas_columns = static_cast<std::uint8_t>(o.atlas.columns);
  spec.materials.atlas_rows = static_cast<std::uint8_t>(o.atlas.rows);
  spec.materials.cell_coverage = o.atlas.coverage;
  FoliageResult res;
  const bool any = (p.leaf_area_index > 0 || p.leaves > 0) && o.leaf_density > 0;
  if (any) {
    res = place_foliage(t, last_level, spec, rng);
  } else {
    t.materials = spec.materials;
  }
  if (o.foliage_result) *o.foliage_result = res;
  // Bark tint heights (fractions of the tree's height in the preset, metres in the tree).
  double top = 0;
  for (const auto& b : t.branches)
    for (const auto& n : b.nodes) top = std::max(top, n.position.y);
  if (p.bark_tint_to > 0) {
    t.materials.bark_tint = p.bark_tint;
    t.materials.bark_tint_from_m = static_cast<float>(p.bark_tint_from * top);
    t.materials.bark_tint_to_m = static_cast<float>(p.bark_tint_to * top);
  }
}

}  // namespace sylva::generate::weber_penn
