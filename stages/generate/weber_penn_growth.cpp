// Pass 1 of the Weber & Penn generator: growth (weber_penn.cpp gives the outline). The only pass
// that draws random numbers for the branches.
//
// Nystad 2010: §5.2.2 (breadth-first, one PRNG), Appendix A (parameters), §3.1 + Appendix B
// (Murray angles for the down angle, clone deviation at splits). Weber & Penn 1995: child counts
// and lengths, shape ratio, curve/curve-back, splits with error diffusion, rotate.
#include <algorithm>
#include <cmath>

#include "stages/generate/natural_rules.h"
#include "stages/generate/weber_penn_passes.h"

namespace sylva::generate::weber_penn {

namespace {

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

// Breadth-first by level: every branch's length, segments, curve, splits and lateral children,
// then the hem heights of the last level. Nothing depends on world positions, so a level's draws
// never depend on deeper ones.
class Grower {
 public:
  Grower(const Preset& p, int levels, Rng& rng, Growth& g)
      : p_(p),
        rng_(rng),
        levels_(levels),
        e_(p.tree_shape_exponent),
        stems_(g.stems),
        plans_(g.plans),
        splits_(g.splits),
        last_level_(g.last_level),
        curve_(g.curve),
        pull_(g.pull) {}

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

 private:
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

  const Preset& p_;
  Rng& rng_;
  int levels_;
  double e_;
  double split_error_ = 0;
  std::vector<Stem>& stems_;
  std::vector<BranchPlan>& plans_;
  std::vector<SplitPlan>& splits_;
  std::vector<std::uint32_t>& last_level_;  // the branches that carry foliage
  std::vector<double>& curve_;
  std::vector<double>& pull_;
};

}  // namespace

Growth grow(const Preset& p, int levels, Rng& rng) {
  Growth g;
  Grower(p, levels, rng, g).grow();
  return g;
}

}  // namespace sylva::generate::weber_penn
