// Pass 2 of the Weber & Penn generator: structure (weber_penn.cpp gives the outline). Per branch,
// in parent-first order, the nodes in arc-length space — segment nodes, split stubs,
// prepended/appended intermediate nodes around every attachment (with the 10 % skip rule), spacing
// nodes — and their radii: W&P taper between nodes, exact da Vinci steps at every junction.
//
// Nystad 2010: §4.2.1–4.2.2 (intermediate nodes, 10 % skip rule), §3.1 + Appendix B (da Vinci
// radii, B.7 at splits), §4.3.2 (maximum node spacing). Weber & Penn 1995: taper and flare.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "stages/generate/natural_rules.h"
#include "stages/generate/weber_penn_passes.h"

namespace sylva::generate::weber_penn {

namespace {

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

// Builds the nodes of one branch after another into a Structure.
class StructureBuilder {
 public:
  StructureBuilder(const Preset& p, const GenerateOptions& o, Growth& g, Structure& out)
      : p_(p),
        o_(o),
        e_(p.tree_shape_exponent),
        stems_(g.stems),
        plans_(g.plans),
        splits_(g.splits),
        node_begin_(out.node_begin),
        s_(out.s),
        radius_(out.radius),
        info_(out.info) {}

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

 private:
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

  const Preset& p_;
  const GenerateOptions& o_;
  double e_;
  std::vector<Stem>& stems_;
  std::vector<BranchPlan>& plans_;
  const std::vector<SplitPlan>& splits_;
  // The result (all branches' nodes concatenated) and the branch being built.
  std::vector<std::uint32_t>& node_begin_;
  std::vector<double>& s_;
  std::vector<double>& radius_;
  std::vector<NodeInfo>& info_;
  std::vector<double> cur_s_, cur_r_;
  std::vector<NodeInfo> cur_info_;
  double cur_out_ = 0;    // outgoing radius of the last node (after its junction's steps)
  double cur_scale_ = 0;  // radius / taper profile, including the da Vinci steps so far
  bool cur_junction_ = false;
  std::uint64_t node_total_ = 0;
};

}  // namespace

Structure build_structure(const Preset& p, const GenerateOptions& o, Growth& g) {
  Structure s;
  StructureBuilder(p, o, g, s).structure();
  return s;
}

}  // namespace sylva::generate::weber_penn
