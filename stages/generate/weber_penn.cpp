// Weber & Penn (1995) parametric trees with Nystad's (2010) natural rules.
//
// Nystad 2010: Appendix A (parameters), §3.1 + Appendix B (da Vinci radii, Murray angles, child
// offset eq. 3.5), §4.1 (process outline), §4.2.1–4.2.2 (intermediate nodes, 10 % skip rule),
// §5.2.1 (primary deviation through parent-relative transforms), §5.2.2 (breadth-first, one
// PRNG), §4.3.2 (maximum node spacing). Weber & Penn 1995: shape ratio, taper/flare, child
// counts and lengths, curve/curve-back, rotate, attraction up.
//
// The generator runs in three passes, mirroring the thesis's process outline:
//   1. Growth (the only pass that draws random numbers): breadth-first by level, every branch's
//      length, segments, curve, splits and lateral children, then the leaves on the last level.
//      Nothing here depends on world positions, so a level's draws never depend on deeper ones.
//   2. Structure: per branch, in parent-first order, the nodes in arc-length space — segment
//      nodes, split stubs, prepended/appended intermediate nodes around every attachment (with
//      the 10 % skip rule), spacing nodes — and their radii: W&P taper between nodes, exact
//      da Vinci steps at every junction.
//   3. World: per branch, in parent-first order, walk the nodes carrying a frame (direction and
//      side); curve and attraction turn it at segment nodes; at junctions the children's frames
//      are taken and then the primary deviation (Murray's angle for the primary) turns the rest
//      of the branch — and with it every later child — which is exactly the thesis's
//      parent-relative propagation, in one O(nodes) pass. Leaves are placed during the walk.
#include "stages/generate/weber_penn.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "libs/tree/vec3.h"
#include "stages/generate/natural_rules.h"

namespace sylva::generate {

using tree::Vec3;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;
constexpr Vec3 kUp{0, 1, 0};

// ---------------------------------------------------------------------------------------------
// Small helpers.

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

const LevelParams& level_params(const Preset& p, std::size_t level) {
  return p.level[std::min(level, p.level.size() - 1)];
}

// W&P taper: the radius of a stem with base radius r_stem and length len at relative position
// z in [0, 1]; with `flare`, the trunk's widening near the base.
double taper_radius(double taper, double r_stem, double len, double z, bool trunk, double flare) {
  z = std::clamp(z, 0.0, 1.0);
  const double unit_taper = taper <= 1 ? taper : taper <= 2 ? 2 - taper : 0;
  const double taper_z = r_stem * (1 - unit_taper * z);
  double r = taper_z;
  if (taper > 1 && taper_z > 0) {
    const double z2 = (1 - z) * len;
    const double depth = (taper < 2 || z2 < taper_z) ? 1 : taper - 2;
    const double z3 = taper < 2 ? z2 : std::abs(z2 - 2 * taper_z * std::floor(z2 / (2 * taper_z) + 0.5));
    if (!(taper < 2 && z3 >= taper_z)) {
      const double q = taper_z * taper_z - (z3 - taper_z) * (z3 - taper_z);
      r = (1 - depth) * taper_z + depth * std::sqrt(std::max(q, 0.0));
    }
  }
  if (trunk) {
    const double y = std::max(0.0, 1 - 8 * z);
    r *= flare * (std::pow(100.0, y) - 1) / 100 + 1;
  }
  return std::max(r, 0.0);
}

// Where lateral i of n sits on its parent's child zone [lo, hi]: evenly spread (W&P), or with
// Clumps k > 0 in k equal groups (child i in group floor(i k / n), so group sizes differ by at
// most one) over the zone less its proximal ClumpBase fraction, each group spread evenly over
// the ClumpSize fraction of its share, centred on that share. Increasing in i either way, so
// children stay ordered by position.
double child_position(const LevelParams& lp, std::uint32_t i, std::uint32_t n, double lo, double hi) {
  if (lp.clumps <= 0) return lo + (i + 0.5) * (hi - lo) / n;
  lo += lp.clump_base * (hi - lo);
  const std::uint64_t k = std::min<std::uint64_t>(static_cast<std::uint64_t>(lp.clumps), n);
  const std::uint64_t c = i * k / n;
  const std::uint64_t first = (c * n + k - 1) / k, next = ((c + 1) * n + k - 1) / k;  // ceil
  const double share = (hi - lo) / static_cast<double>(k);
  const double width = lp.clump_size * share;
  const double start = lo + (static_cast<double>(c) + 0.5) * share - 0.5 * width;
  return start + (static_cast<double>(i - first) + 0.5) * width / static_cast<double>(next - first);
}

// ---------------------------------------------------------------------------------------------
// Pass 1 records.

// One stem: a W&P branch with all its clones (they share length, taper and segment length).
struct Stem {
  double length = 0;   // m
  double radius = 0;   // base radius the taper profile is relative to (m); set in pass 2
  double seg_len = 0;  // m
  int curve_res = 1;
  double offset = 0;  // attachment offset along the parent stem (m), laterals only
  double parent_length = 0;
  bool trunk = false;
};

// How one split groups n members (the primary continuation and n − 1 clones).
struct SplitPlan {
  int base = 0;  // segment node index on the splitting branch
  int n = 2;     // members
  double primary_azimuth = 0, primary_deviation = 0;
  std::uint32_t first_clone = 0;  // clones are consecutive plans
};

struct BranchPlan {
  std::int32_t parent = -1;
  std::uint32_t level = 0;
  bool clone = false;
  std::uint32_t stem = 0;
  int nseg = 1;                // segments of this branch (clones: the stem's remaining ones)
  int seg_offset = 0;          // stem segment index of this branch's first segment
  double attach_s = 0;         // lateral: arc position on the parent
  double azimuth = 0;          // around the parent's frame at the junction
  double deviation = 0;        // lateral: down angle; clone: split deviation (rad)
  double primary_angle = 0;    // lateral: Murray's primary deviation x it causes (rad)
  double ratio = 1;            // lateral: S_s; clone: n (members of its split)
  double hem = 0;              // last level with Hem > 0: the height (m) it ends at; 0 = none
  std::uint32_t curve_at = 0;  // curve[] per segment node 0..nseg in a shared pool
  std::int64_t pull_at = -1;   // trunk split compensation per segment node, or -1
  std::uint32_t first_child = 0, child_count = 0;  // laterals, consecutive, by attach_s
  std::uint32_t first_split = 0, split_count = 0;  // splits, by base
  // Set in pass 2.
  double start_radius = 0;
  std::uint32_t junction = 0;  // node of the parent it grows from
};

// Per-node data of pass 2 that pass 3 needs (nodes of all branches, concatenated).
struct NodeInfo {
  double s = 0;
  int base = -1;                                   // segment node index, or -1 for inserted nodes
  std::uint32_t first_child = 0, child_count = 0;  // laterals at this junction (plan ids)
  std::int32_t split = -1;                         // split plan at this node
};

class Generator {
 public:
  Generator(const Preset& p, const GenerateOptions& o, Rng& rng)
      : p_(p), o_(o), rng_(rng), levels_(o.levels > 0 ? o.levels : p.levels) {
    e_ = p.tree_shape_exponent;
  }

  tree::Tree run() {
    grow();
    structure();
    tree::Tree t;
    t.name = o_.name;
    t.materials = p_.materials;
    world(t);
    foliage(t);
    return t;
  }

 private:
  // -------------------------------------------------------------------------------------------
  // Pass 1: growth.

  void grow() {
    std::vector<std::uint32_t> current;
    // The trunk.
    {
      const LevelParams& lp = level_params(p_, 0);
      Stem st;
      st.trunk = true;
      const double scale = p_.scale + p_.scale_v * rng_.signed_unit();
      st.length = std::max(1e-3, (lp.length + lp.length_v * rng_.signed_unit()) * scale);
      st.curve_res = lp.curve_res;
      st.seg_len = st.length / lp.curve_res;
      stems_.push_back(st);
      BranchPlan b;
      b.nseg = lp.curve_res;
      plans_.push_back(b);
      current.push_back(0);
    }
    for (int level = 0; level < levels_; ++level) {
      if (level > 0) {
        std::vector<std::uint32_t> next;
        for (std::uint32_t parent : current) add_children(parent, static_cast<std::uint32_t>(level), next);
        current = std::move(next);
      }
      split_error_ = 0;
      // Clones are appended while we iterate: they are grown in the same level.
      for (std::size_t i = 0; i < current.size(); ++i) grow_branch(current[i], current);
    }
    // Hem: one draw per branch of the last level, after all the growth draws, so a hem changes
    // nothing but where those branches end (pass 3).
    if (p_.hem > 0)
      for (std::uint32_t id : current)
        plans_[id].hem = p_.hem * stems_[0].length * (1 + p_.hem_v * rng_.signed_unit());
    last_level_ = std::move(current);
  }

  // Curve, trunk split compensation and splits of one branch.
  void grow_branch(std::uint32_t id, std::vector<std::uint32_t>& level_list) {
    const std::uint32_t level = plans_[id].level;
    const LevelParams& lp = level_params(p_, level);
    const Stem stem = stems_[plans_[id].stem];
    const int nseg = plans_[id].nseg;
    // Curve per segment node (W&P: Curve/CurveRes per segment, or Curve and CurveBack over the
    // two halves; CurveV/CurveRes random per segment).
    plans_[id].curve_at = static_cast<std::uint32_t>(curve_.size());
    for (int j = 0; j <= nseg; ++j) {
      double c = 0;
      if (j >= 1 && j < nseg) {
        const int g = plans_[id].seg_offset + j;
        if (lp.curve_back == 0) {
          c = lp.curve / lp.curve_res;
        } else {
          const double half = std::max(1.0, lp.curve_res / 2.0);
          c = (g < lp.curve_res / 2.0 ? lp.curve : lp.curve_back) / half;
        }
        c = (c + lp.curve_v / lp.curve_res * rng_.signed_unit()) * kDeg;
      }
      curve_.push_back(c);
    }
    if (level == 0) {
      plans_[id].pull_at = static_cast<std::int64_t>(pull_.size());
      pull_.resize(pull_.size() + static_cast<std::size_t>(nseg) + 1, 0.0);
    }
    // Splits at interior segment nodes: BaseSplits after the first trunk segment, SegSplits
    // (error-diffused, W&P) elsewhere.
    plans_[id].first_split = static_cast<std::uint32_t>(splits_.size());
    for (int j = 1; j < nseg; ++j) {
      const int g = plans_[id].seg_offset + j;
      int count;
      if (level == 0 && g == 1 && !plans_[id].clone && p_.base_splits > 0) {
        count = p_.base_splits;
      } else {
        count = static_cast<int>(std::floor(lp.seg_splits + split_error_ + 0.5));
        split_error_ -= count - lp.seg_splits;
      }
      count = std::clamp(count, 0, 8);
      if (count == 0) continue;
      const int n = count + 1;
      const double theta = clone_deviation(e_, n);
      SplitPlan sp;
      sp.base = j;
      sp.n = n;
      const double psi = rng_.uniform(0, 2 * kPi);
      sp.primary_azimuth = psi;
      sp.primary_deviation = std::max(0.0, theta + lp.split_angle_v * kDeg * rng_.signed_unit());
      sp.first_clone = static_cast<std::uint32_t>(plans_.size());
      for (int m = 1; m < n; ++m) {
        BranchPlan c;
        c.parent = static_cast<std::int32_t>(id);
        c.level = level;
        c.clone = true;
        c.stem = plans_[id].stem;
        c.seg_offset = g;
        c.nseg = stem.curve_res - g;
        c.azimuth = psi + 2 * kPi * m / n;
        c.deviation = std::max(0.0, theta + lp.split_angle_v * kDeg * rng_.signed_unit());
        c.ratio = n;
        level_list.push_back(static_cast<std::uint32_t>(plans_.size()));
        plans_.push_back(c);
      }
      // Trunk: W&P's split correction — the members turn back towards the vertical over their
      // remaining segments.
      if (level == 0) {
        const int remaining = nseg - j;
        for (int k = j + 1; k < nseg; ++k)
          pull_[static_cast<std::size_t>(plans_[id].pull_at) + k] += theta / remaining;
      }
      splits_.push_back(sp);
      ++plans_[id].split_count;
    }
    if (plans_[id].clone && level == 0) {
      // A trunk clone carries its parent split's correction over its own segments.
      const double theta = clone_deviation(e_, static_cast<int>(plans_[id].ratio));
      for (int k = 1; k < nseg; ++k) pull_[static_cast<std::size_t>(plans_[id].pull_at) + k] += theta / nseg;
    }
  }

  // The lateral children of `parent` (one level up), W&P counts and lengths, natural angles.
  void add_children(std::uint32_t parent, std::uint32_t level, std::vector<std::uint32_t>& out) {
    const BranchPlan& pb = plans_[parent];
    const Stem ps = stems_[pb.stem];
    const LevelParams& lp = level_params(p_, level);  // the children's level
    const double branch_len = pb.nseg * ps.seg_len;
    const double branch_start = pb.seg_offset * ps.seg_len;  // stem offset of s = 0
    // Children per metre of stem (W&P).
    double count_stem;
    double zone_start = 0;  // stem offset where children may start
    if (pb.level == 0) {
      count_stem = lp.branches;
      zone_start = p_.base_size * ps.length;
    } else if (pb.level == 1) {
      const LevelParams& own = level_params(p_, 1);
      const double max_len = std::max(1e-9, own.length + own.length_v);
      count_stem = lp.branches * (0.2 + 0.8 * (ps.length / ps.parent_length) / max_len);
    } else {
      count_stem = lp.branches * (1.0 - 0.5 * ps.offset / ps.parent_length);
    }
    const double zone_len_stem = ps.length - zone_start;
    if (count_stem <= 0 || zone_len_stem <= 0) return;
    const double density = count_stem / zone_len_stem;
    const double lo = std::max(zone_start - branch_start, pb.clone ? 0.25 * ps.seg_len : 0.0);
    const double hi = branch_len;
    if (hi <= lo) return;
    const auto n = static_cast<std::uint32_t>(std::floor(density * (hi - lo) + 0.5));
    if (n == 0) return;
    plans_[parent].first_child = static_cast<std::uint32_t>(plans_.size());
    const MurrayAngles murray = murray_angles_for_ratio(e_, lp.branch_ratio);
    double azimuth = 0;
    double alternate = 1;
    for (std::uint32_t i = 0; i < n; ++i) {
      const double s = child_position(lp, i, n, lo, hi);
      const double offset = branch_start + s;  // on the parent stem
      // Three draws per child, always, in this order: length, azimuth, down angle.
      const double r_len = rng_.signed_unit();
      const double r_rot = rng_.signed_unit();
      const double r_down = rng_.signed_unit();
      double length;
      if (level == 1) {
        const double base_len = p_.base_size * ps.length;
        const double ratio = (ps.length - offset) / std::max(1e-9, ps.length - base_len);
        length = ps.length * (lp.length + lp.length_v * r_len) * crown_shape(ratio);
      } else {
        length = (lp.length + lp.length_v * r_len) * (ps.length - 0.6 * offset);
      }
      if (lp.rotate >= 0) {
        azimuth = std::fmod(azimuth + (lp.rotate + lp.rotate_v * r_rot) * kDeg, 2 * kPi);
      } else {
        alternate = -alternate;
        azimuth = alternate * (180 + lp.rotate + lp.rotate_v * r_rot) * kDeg;
      }
      double down = murray.secondary;
      if (lp.down_angle_v >= 0) {
        down += lp.down_angle_v * kDeg * r_down;
      } else {
        const double base_len = pb.level == 0 ? p_.base_size * ps.length : 0;
        const double ratio = (ps.length - offset) / std::max(1e-9, ps.length - base_len);
        down -= lp.down_angle_v * kDeg * (1 - 2 * shape_ratio(0, std::clamp(ratio, 0.0, 1.0)));
      }
      if (length < 1e-4) continue;
      Stem st;
      st.length = length;
      st.curve_res = lp.curve_res;
      st.seg_len = length / lp.curve_res;
      st.offset = offset;
      st.parent_length = ps.length;
      BranchPlan c;
      c.parent = static_cast<std::int32_t>(parent);
      c.level = level;
      c.stem = static_cast<std::uint32_t>(stems_.size());
      c.nseg = lp.curve_res;
      c.attach_s = s;
      c.azimuth = azimuth;
      c.deviation = std::clamp(down, 0.02, kPi - 0.02);
      c.primary_angle = murray.primary;
      c.ratio = lp.branch_ratio;
      stems_.push_back(st);
      out.push_back(static_cast<std::uint32_t>(plans_.size()));
      plans_.push_back(c);
      ++plans_[parent].child_count;
    }
  }

  // W&P's shape ratio for level-1 lengths; with a ShapeFloor other than W&P's 0.2, the ratios of
  // shapes 0-2 (0.2 + 0.8 f(r)) become ShapeFloor + (1 - ShapeFloor) f(r).
  double crown_shape(double ratio) const {
    const double w = shape_ratio(p_.shape, ratio);
    if (p_.shape_floor == kWeberPennShapeFloor) return w;
    return p_.shape_floor + (1 - p_.shape_floor) * (w - kWeberPennShapeFloor) / (1 - kWeberPennShapeFloor);
  }

  // -------------------------------------------------------------------------------------------
  // Pass 2: nodes in arc-length space, radii with exact da Vinci junctions.

  double stem_z(const BranchPlan& b, double s) const {
    const Stem& st = stems_[b.stem];
    return (b.seg_offset * st.seg_len + s) / st.length;
  }

  double profile(const BranchPlan& b, double s) const {
    const Stem& st = stems_[b.stem];
    return taper_radius(level_params(p_, b.level).taper, st.radius, st.length, stem_z(b, s), st.trunk,
                        p_.flare);
  }

  // Appends node (s, base) to the branch being built. Its radius follows the taper profile from
  // the previous node, or is exactly the previous junction's outgoing radius (da Vinci step).
  // Spacing nodes are inserted first if the gap exceeds max_node_spacing.
  void push_node(const BranchPlan& b, double s, int base) {
    if (!cur_s_.empty() && o_.max_node_spacing > 0) {
      const double gap = s - cur_s_.back();
      const auto extra = static_cast<int>(std::ceil(gap / o_.max_node_spacing - 1e-9)) - 1;
      const double from = cur_s_.back();
      for (int i = 1; i <= extra; ++i) push_one(b, from + gap * i / (extra + 1), -1);
    }
    push_one(b, s, base);
  }

  void push_one(const BranchPlan& b, double s, int base) {
    // Radii follow the taper profile scaled by the da Vinci steps taken so far; the node right
    // after a junction takes the junction's outgoing radius exactly (no taper over that short
    // segment), and the node after it returns to the profile, so no taper is lost overall.
    double r;
    if (cur_s_.empty()) {
      r = b.start_radius;
      const double p0 = profile(b, s);
      cur_scale_ = p0 > 0 ? r / p0 : 0.0;
    } else if (cur_junction_) {
      r = cur_out_;
    } else {
      r = cur_scale_ * profile(b, s);
    }
    if (++node_total_ > o_.max_nodes)
      throw std::length_error("the tree exceeds the node budget of " + std::to_string(o_.max_nodes) +
                              " nodes (lower Levels, Branches or CurveRes, or raise max_node_spacing)");
    cur_s_.push_back(s);
    cur_r_.push_back(r);
    NodeInfo ni;
    ni.s = s;
    ni.base = base;
    cur_info_.push_back(ni);
    cur_out_ = r;
    cur_junction_ = false;
  }

  // Makes the last node a junction for lateral `child`: the child takes C_s of the outgoing
  // radius, the branch continues with C_p of it, so r^E = r_out^E + r_child^E exactly.
  void attach_lateral(std::uint32_t child) {
    BranchPlan& c = plans_[child];
    const RadiusSplit k = radius_constants(e_, c.ratio);
    NodeInfo& ni = cur_info_.back();
    if (ni.child_count == 0) ni.first_child = child;
    ++ni.child_count;
    c.start_radius = k.secondary * cur_out_;
    c.junction = static_cast<std::uint32_t>(cur_s_.size() - 1);
    stems_[c.stem].radius = c.start_radius;
    cur_out_ *= k.primary;
    cur_scale_ *= k.primary;
    cur_junction_ = true;
  }

  void structure() {
    node_begin_.resize(plans_.size() + 1);
    radius_.reserve(plans_.size() * 8);
    // The trunk's stem radius (W&P: length x Ratio; Nystad drops 0Scale); its base radius
    // includes the flare.
    stems_[0].radius = stems_[0].length * p_.ratio;
    plans_[0].start_radius =
        taper_radius(level_params(p_, 0).taper, stems_[0].radius, stems_[0].length, 0, true, p_.flare);
    for (std::uint32_t id = 0; id < plans_.size(); ++id) {
      node_begin_[id] = static_cast<std::uint32_t>(s_.size());
      build_branch(id);
      s_.insert(s_.end(), cur_s_.begin(), cur_s_.end());
      radius_.insert(radius_.end(), cur_r_.begin(), cur_r_.end());
      info_.insert(info_.end(), cur_info_.begin(), cur_info_.end());
    }
    node_begin_[plans_.size()] = static_cast<std::uint32_t>(s_.size());
  }

  void build_branch(std::uint32_t id) {
    cur_s_.clear();
    cur_r_.clear();
    cur_info_.clear();
    cur_junction_ = false;
    const BranchPlan b = plans_[id];
    const Stem& st = stems_[b.stem];
    const double seg = st.seg_len;
    std::uint32_t next_child = b.first_child;
    const std::uint32_t end_child = b.first_child + b.child_count;
    std::uint32_t next_split = b.first_split;
    // A clone's first node is its stub, one clone radius (at most 20 % of a segment) along the
    // split direction; roots and laterals start at their segment node 0.
    int j0 = 0;
    if (b.clone) {
      push_node(b, std::min(b.start_radius, 0.2 * seg), -1);
      j0 = 1;
    }
    for (int j = j0; j <= b.nseg; ++j) {
      const double sj = j * seg;
      // Attachments before this segment node: prepended node (or the nearest node if it would
      // be within 10 % of a segment of it, or behind it), the junction, the appended node.
      while (next_child < end_child && plans_[next_child].attach_s < sj) {
        const std::uint32_t c = next_child++;
        const double sa = plans_[c].attach_s;
        const double r_est = radius_constants(e_, plans_[c].ratio).secondary * estimate_radius(b, sa);
        const double pre = sa - r_est;
        if (pre > cur_s_.back() + 0.1 * seg) push_node(b, pre, -1);
        attach_lateral(c);
        // The appended node (no skip rule in the thesis) unless it would reach the next segment
        // node or pass the next attachment's prepended node.
        const double app = sa + r_est;
        const bool next_overlaps = next_child < end_child && plans_[next_child].attach_s - r_est <= app;
        if (app < sj - 0.25 * r_est && !next_overlaps) push_node(b, app, -1);
      }
      push_node(b, sj, j);
      // A split at this segment node: the clones and the continuation share the radius equally
      // (B.7); the continuation gets its own stub so the step is exact.
      if (next_split < b.first_split + b.split_count && splits_[next_split].base == j) {
        const SplitPlan& sp = splits_[next_split];
        cur_info_.back().split = static_cast<std::int32_t>(next_split);
        const double f = clone_radius_factor(e_, sp.n);
        for (int m = 1; m < sp.n; ++m) {
          BranchPlan& c = plans_[sp.first_clone + static_cast<std::uint32_t>(m - 1)];
          c.start_radius = f * cur_out_;
          c.junction = static_cast<std::uint32_t>(cur_s_.size() - 1);
        }
        cur_out_ *= f;
        cur_scale_ *= f;
        cur_junction_ = true;
        ++next_split;
        const double stub = std::min(cur_out_, 0.2 * seg);
        const bool child_soon =
            next_child < end_child && plans_[next_child].attach_s <= sj + stub + 0.1 * seg;
        if (j < b.nseg && !child_soon) push_node(b, sj + stub, -1);
      }
    }
  }

  // The radius the profile would give at s, continuing from the last node.
  double estimate_radius(const BranchPlan& b, double s) const { return cur_scale_ * profile(b, s); }

  // -------------------------------------------------------------------------------------------
  // Pass 3: world positions, junction frames, primary deviation, leaves.

  struct Start {
    Vec3 position;
    Frame frame;
    double parent_radius = 0;
  };

  void world(tree::Tree& t) {
    t.branches.resize(plans_.size());
    std::vector<Start> start(plans_.size());
    start[0].frame = {kUp, {1, 0, 0}};
    for (std::uint32_t id = 0; id < plans_.size(); ++id) {
      const BranchPlan& b = plans_[id];
      tree::Branch& out = t.branches[id];
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
      const int curve_res = stems_[b.stem].curve_res;
      const double attraction = b.level >= 2 ? p_.attraction_up : 0.0;
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
          // The first node below the hem ends the branch: at the crossing when the previous node
          // is above it (or at that node when the crossing is within a millimetre of it and the
          // branch keeps two nodes without it); at this node when the branch was already below.
          const tree::Node prev = out.nodes[k - n0 - 1];
          out.nodes[k - n0] = {pos, radius_[k]};
          out.nodes.resize(k - n0 + 1);
          if (prev.position.y >= b.hem) {
            const double at = (prev.position.y - b.hem) / (prev.position.y - pos.y);
            if (at * (s_[k] - s_[k - 1]) < 1e-3 && k - 1 > n0)
              out.nodes.pop_back();
            else
              out.nodes.back() = {prev.position + (pos - prev.position) * at,
                                  prev.radius + (radius_[k] - prev.radius) * at};
          }
          break;
        }
        out.nodes[k - n0] = {pos, radius_[k]};
        // Turns at interior segment nodes: Curve about the side axis, then AttractionUp (and the
        // trunk's split correction) towards the vertical.
        if (ni.base >= 1 && ni.base < b.nseg) {
          const double c = curve_[b.curve_at + static_cast<std::uint32_t>(ni.base)];
          if (c != 0) f.turn(f.side, c);
          double pull = 0;
          if (b.pull_at >= 0)
            pull = pull_[static_cast<std::size_t>(b.pull_at) + static_cast<std::size_t>(ni.base)];
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
        // Junction: children take the frame as it is (the direction of the segment they grow
        // from); then the primary deviation turns the rest of this branch away from each child.
        if (ni.child_count > 0 || ni.split >= 0) {
          const Frame pre = f;
          if (ni.split >= 0) {
            const SplitPlan& sp = splits_[static_cast<std::size_t>(ni.split)];
            for (int m = 1; m < sp.n; ++m) {
              const std::uint32_t c = sp.first_clone + static_cast<std::uint32_t>(m - 1);
              start[c] = child_start(pre, pos, plans_[c].azimuth, plans_[c].deviation, radius_[k]);
            }
            const Vec3 o = pre.out(sp.primary_azimuth);
            f.turn(tree::normalized(tree::cross(pre.d, o)), sp.primary_deviation);
          }
          for (std::uint32_t c = ni.first_child; c < ni.first_child + ni.child_count; ++c) {
            start[c] = child_start(pre, pos, plans_[c].azimuth, plans_[c].deviation, radius_[k]);
            const Vec3 o = pre.out(plans_[c].azimuth);
            f.turn(tree::normalized(tree::cross(pre.d, o)), -plans_[c].primary_angle);
          }
        }
        // TrunkUp: a level-0 branch turns back towards the vertical after this node's turns.
        if (b.level == 0 && p_.trunk_up > 0) {
          const Vec3 axis = tree::cross(f.d, kUp);
          const double al = tree::length(axis);
          if (al > 1e-12)
            f.turn(axis / al, p_.trunk_up * std::acos(std::clamp(tree::dot(f.d, kUp), -1.0, 1.0)));
        }
      }
    }
  }

  // Ground: turns f up (about the horizontal axis d x up) just enough that a step of `ds` from
  // `pos` ends at least ground_clearance(r) above y = 0. Never turns past the vertical.
  static void lift(Frame& f, Vec3 pos, double ds, double r) {
    if (!(ds > 0)) return;
    const double want = (ground_clearance(r) - pos.y) / ds;
    if (f.d.y >= want) return;
    const double target = std::asin(std::clamp(want, -1.0, 1.0));
    const double now = std::asin(std::clamp(f.d.y, -1.0, 1.0));
    Vec3 axis = tree::cross(f.d, kUp);
    axis = tree::length(axis) > 1e-9 ? tree::normalized(axis) : f.side;
    f.turn(axis, target - now);
  }

  static Start child_start(const Frame& pre, Vec3 pos, double azimuth, double deviation, double r_parent) {
    const Vec3 o = pre.out(azimuth);
    const Vec3 axis = tree::normalized(tree::cross(pre.d, o));
    Start s;
    s.position = pos;
    s.frame.d = tree::normalized(pre.d * std::cos(deviation) + o * std::sin(deviation));
    s.frame.side = axis;  // Curve bends the child in the plane of its down angle
    s.parent_radius = r_parent;
    return s;
  }

  // Foliage on the last level (foliage_placement.h), then the bark tint heights.
  void foliage(tree::Tree& t) {
    FoliageSpec spec;
    const bool cards = o_.foliage == FoliageMode::kCards;
    spec.mode =
        cards ? FoliageSpec::Mode::kCards
              : (p_.foliage == Foliage::kNeedles ? FoliageSpec::Mode::kNeedles : FoliageSpec::Mode::kLeaves);
    spec.target_lai = p_.leaf_area_index * o_.leaf_density;
    spec.count = p_.leaves * o_.leaf_density;
    spec.zone = p_.foliage_zone;
    spec.leaf_scale = p_.leaf_scale;
    spec.leaf_scale_x = p_.leaf_scale_x;
    spec.natural_angle = murray_angles_for_ratio(e_, p_.leaf.branch_ratio).secondary;
    spec.down_angle_v = p_.leaf.down_angle_v * kDeg;
    spec.rotate = p_.leaf.rotate * kDeg;
    spec.rotate_v = p_.leaf.rotate_v * kDeg;
    spec.card = p_.card;
    spec.card.length *= p_.card_scale;
    spec.materials = t.materials;
    spec.materials.leaf_kind = !cards                            ? tree::LeafKind::kLeaves
                               : p_.foliage == Foliage::kNeedles ? tree::LeafKind::kShootCards
                                                                 : tree::LeafKind::kTwigCards;
    spec.materials.atlas_columns = static_cast<std::uint8_t>(o_.atlas.columns);
    spec.materials.atlas_rows = static_cast<std::uint8_t>(o_.atlas.rows);
    spec.materials.cell_coverage = o_.atlas.coverage;
    FoliageResult res;
    const bool any = (p_.leaf_area_index > 0 || p_.leaves > 0) && o_.leaf_density > 0;
    if (any) {
      res = place_foliage(t, last_level_, spec, rng_);
    } else {
      t.materials = spec.materials;
    }
    if (o_.foliage_result) *o_.foliage_result = res;
    // Bark tint heights (fractions of the tree's height in the preset, metres in the tree).
    double top = 0;
    for (const auto& b : t.branches)
      for (const auto& n : b.nodes) top = std::max(top, n.position.y);
    if (p_.bark_tint_to > 0) {
      t.materials.bark_tint = p_.bark_tint;
      t.materials.bark_tint_from_m = static_cast<float>(p_.bark_tint_from * top);
      t.materials.bark_tint_to_m = static_cast<float>(p_.bark_tint_to * top);
    }
  }

  const Preset& p_;
  const GenerateOptions& o_;
  Rng& rng_;
  int levels_;
  double e_ = 2.49;
  double split_error_ = 0;
  std::vector<Stem> stems_;
  std::vector<BranchPlan> plans_;
  std::vector<SplitPlan> splits_;
  std::vector<std::uint32_t> last_level_;  // the branches that carry foliage
  std::vector<double> curve_, pull_;
  // Pass 2 results (all branches' nodes concatenated) and the branch being built.
  std::vector<std::uint32_t> node_begin_;
  std::vector<double> s_, radius_;
  std::vector<NodeInfo> info_;
  std::vector<double> cur_s_, cur_r_;
  std::vector<NodeInfo> cur_info_;
  double cur_out_ = 0;    // outgoing radius of the last node (after its junction's steps)
  double cur_scale_ = 0;  // radius / taper profile, including the da Vinci steps so far
  bool cur_junction_ = false;
  std::uint64_t node_total_ = 0;
};

}  // namespace

double shape_ratio(int shape, double r) {
  switch (shape) {
    case 0:
      return 0.2 + 0.8 * r;  // conical
    case 1:
      return 0.2 + 0.8 * std::sin(kPi * r);  // spherical
    case 2:
      return 0.2 + 0.8 * std::sin(0.5 * kPi * r);  // hemispherical
    case 3:
      return 1.0;  // cylindrical
    case 4:
      return 0.5 + 0.5 * r;  // tapered cylindrical
    case 5:
      return r <= 0.7 ? r / 0.7 : (1 - r) / 0.3;  // flame
    case 6:
      return 1 - 0.8 * r;  // inverse conical
    case 7:
      return r <= 0.7 ? 0.5 + 0.5 * r / 0.7 : 0.5 + 0.5 * (1 - r) / 0.3;  // tend flame
    default:
      return 1.0;
  }
}

void validate_preset(const Preset& p) {
  auto need = [](bool ok, const std::string& key, const std::string& rule) {
    if (!ok) throw PresetError(key, key + " must be " + rule);
  };
  need(p.shape >= 0 && p.shape <= 7, "Shape", "0..7");
  need(p.levels >= 1 && p.levels <= 8, "Levels", "1..8");
  need(p.scale > 0 && p.scale <= 200, "Scale", "in (0, 200]");
  need(p.scale_v >= 0 && p.scale_v < p.scale, "ScaleV", "in [0, Scale)");
  need(p.base_size >= 0 && p.base_size < 1, "BaseSize", "in [0, 1)");
  need(p.ratio > 0 && p.ratio < 1, "Ratio", "in (0, 1)");
  need(p.flare >= 0 && p.flare <= 10, "Flare", "in [0, 10]");
  need(p.base_splits >= 0 && p.base_splits <= 8, "BaseSplits", "0..8");
  need(std::abs(p.attraction_up) <= 10, "AttractionUp", "in [-10, 10]");
  need(p.tree_shape_exponent >= 1.5 && p.tree_shape_exponent <= 4, "TreeShapeExponent", "in [1.5, 4]");
  need(p.leaves >= 0 && p.leaves <= 5e6, "Leaves", "in [0, 5000000]");
  need(p.leaf_scale > 0 && p.leaf_scale <= 2, "LeafScale", "in (0, 2]");
  need(p.leaf_scale_x > 0 && p.leaf_scale_x <= 4, "LeafScaleX", "in (0, 4]");
  need(p.leaf_area_index >= 0 && p.leaf_area_index <= 20, "LeafAreaIndex", "in [0, 20]");
  need(p.foliage_zone > 0 && p.foliage_zone <= 1, "FoliageZone", "in (0, 1]");
  need(p.card_scale >= 0.25 && p.card_scale <= 4, "CardScale", "in [0.25, 4]");
  need(p.hem >= 0 && p.hem < 1, "Hem", "in [0, 1)");
  need(p.hem_v >= 0 && p.hem_v < 1, "HemV", "in [0, 1)");
  need(p.trunk_up >= 0 && p.trunk_up <= 1, "TrunkUp", "in [0, 1]");
  need(p.shape_floor >= 0 && p.shape_floor <= 1, "ShapeFloor", "in [0, 1]");
  need(p.pendulous >= 0 && p.pendulous <= 1, "Pendulous", "in [0, 1]");
  need(p.pendulous == 0 || p.attraction_up < 0, "Pendulous", "0 unless AttractionUp < 0");
  need(p.shape_floor == kWeberPennShapeFloor || p.shape <= 2, "ShapeFloor",
       "0.2 (W&P's) unless Shape is 0, 1 or 2");
  need(p.card.length > 0 && p.card.length <= 5, "card.length_m", "in (0, 5]");
  need(p.card.aspect > 0 && p.card.aspect <= 4, "card.aspect", "in (0, 4]");
  need(p.card.min_layers >= 1 && p.card.min_layers <= p.card.max_layers && p.card.max_layers <= 4,
       "card.layers", "[min, max] with 1 <= min <= max <= 4");
  need(p.card.light_bias >= 0 && p.card.light_bias <= 1, "card.light_bias", "in [0, 1]");
  need(p.bark_tint_from >= 0 && p.bark_tint_from <= p.bark_tint_to && p.bark_tint_to <= 1,
       "textures.bark.lower_tint", "heights 0 <= below <= above <= 1 (fractions of the tree's height)");
  need(!p.level.empty(), "levels", "a list with at least the trunk");
  for (std::size_t i = 0; i < p.level.size(); ++i) {
    const LevelParams& l = p.level[i];
    const std::string at = "levels[" + std::to_string(i) + "].";
    need(l.branches >= 0 && l.branches <= 10000, at + "Branches", "in [0, 10000]");
    need(l.length > 0 && l.length <= 100, at + "Length", "in (0, 100]");
    need(l.length_v >= 0 && l.length_v < l.length, at + "LengthV", "in [0, Length)");
    need(l.taper >= 0 && l.taper <= 3, at + "Taper", "in [0, 3]");
    need(l.seg_splits >= 0 && l.seg_splits <= 4, at + "SegSplits", "in [0, 4]");
    need(l.split_angle_v >= 0 && l.split_angle_v <= 90, at + "SplitAngleV", "in [0, 90]");
    need(l.curve_res >= 1 && l.curve_res <= 100, at + "CurveRes", "1..100");
    need(std::abs(l.curve) <= 720, at + "Curve", "in [-720, 720]");
    need(std::abs(l.curve_back) <= 720, at + "CurveBack", "in [-720, 720]");
    need(l.curve_v >= 0 && l.curve_v <= 720, at + "CurveV", "in [0, 720]");
    need(std::abs(l.down_angle_v) <= 180, at + "DownAngleV", "in [-180, 180]");
    need(std::abs(l.rotate) <= 360, at + "Rotate", "in [-360, 360]");
    need(l.rotate_v >= 0 && l.rotate_v <= 360, at + "RotateV", "in [0, 360]");
    need(l.branch_ratio > 0 && l.branch_ratio <= 1, at + "BranchRatio", "in (0, 1]");
    need(l.clumps >= 0 && l.clumps <= 100, at + "Clumps", "0..100");
    need(l.clump_size > 0 && l.clump_size <= 1, at + "ClumpSize", "in (0, 1]");
    need(l.clump_base >= 0 && l.clump_base < 1, at + "ClumpBase", "in [0, 1)");
  }
  need(std::abs(p.leaf.down_angle_v) <= 180, "leaf.DownAngleV", "in [-180, 180]");
  need(std::abs(p.leaf.rotate) <= 360, "leaf.Rotate", "in [-360, 360]");
  need(p.leaf.rotate_v >= 0 && p.leaf.rotate_v <= 360, "leaf.RotateV", "in [0, 360]");
  need(p.leaf.branch_ratio > 0 && p.leaf.branch_ratio <= 1, "leaf.BranchRatio", "in (0, 1]");
}

tree::Tree generate_tree(const Preset& preset, const GenerateOptions& options, Rng& rng) {
  validate_preset(preset);
  if (options.levels < 0 || options.levels > 8) throw std::invalid_argument("levels must be 0..8");
  if (!(options.max_node_spacing >= 0)) throw std::invalid_argument("max_node_spacing must be >= 0");
  if (!(options.leaf_density >= 0)) throw std::invalid_argument("leaf_density must be >= 0");
  Generator g(preset, options, rng);
  return g.run();
}

}  // namespace sylva::generate
