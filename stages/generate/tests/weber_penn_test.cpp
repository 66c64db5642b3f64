#include "stages/generate/weber_penn.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "libs/tree/frames.h"
#include "libs/tree/sylt_format.h"
#include "stages/generate/natural_rules.h"

namespace sylva::generate {
namespace {

using tree::Vec3;

// A three-level broadleaf with splits everywhere; every parameter set to something non-trivial.
Preset busy_preset() {
  Preset p;
  p.shape = 1;
  p.levels = 3;
  p.scale = 12;
  p.scale_v = 2;
  p.base_size = 0.15;
  p.ratio = 0.025;
  p.flare = 0.6;
  p.base_splits = 1;
  p.attraction_up = 0.5;
  p.tree_shape_exponent = 2.49;
  p.leaves = 3000;
  p.leaf_scale = 0.1;
  p.leaf_scale_x = 0.5;
  LevelParams trunk;
  trunk.curve_res = 6;
  trunk.curve_v = 20;
  trunk.seg_splits = 0.2;
  trunk.split_angle_v = 5;
  LevelParams l1;
  l1.branches = 25;
  l1.length = 0.5;
  l1.length_v = 0.1;
  l1.curve_res = 5;
  l1.curve = -20;
  l1.curve_v = 40;
  l1.curve_back = 10;
  l1.seg_splits = 0.2;
  l1.down_angle_v = 10;
  l1.rotate = 140;
  l1.rotate_v = 15;
  l1.branch_ratio = 0.5;
  LevelParams l2 = l1;
  l2.branches = 12;
  l2.curve_res = 3;
  l2.seg_splits = 0;
  l2.rotate = -90;  // alternating
  l2.branch_ratio = 0.4;
  p.level = {trunk, l1, l2};
  return p;
}

// The same tree with every source of angle noise and bending switched off (including the
// trunk's split correction, which bends like Curve), so that the geometry at junctions is
// exactly the natural rules'. Splits remain on level 1.
Preset exact_preset() {
  Preset p = busy_preset();
  p.attraction_up = 0;
  p.base_splits = 0;
  p.level[0].seg_splits = 0;
  for (LevelParams& l : p.level) {
    l.curve = l.curve_v = l.curve_back = 0;
    l.down_angle_v = 0;
    l.split_angle_v = 0;
  }
  return p;
}

tree::Tree make(const Preset& p, std::uint64_t seed, GenerateOptions o = {}) {
  Rng rng(seed, "tree");
  return generate_tree(p, o, rng);
}

double angle(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(tree::dot(tree::normalized(a), tree::normalized(b)), -1.0, 1.0));
}

// Children of every (branch, node), in branch order.
std::map<std::pair<std::size_t, std::uint32_t>, std::vector<std::size_t>> junctions(const tree::Tree& t) {
  std::map<std::pair<std::size_t, std::uint32_t>, std::vector<std::size_t>> j;
  for (std::size_t i = 0; i < t.branches.size(); ++i)
    if (t.branches[i].parent >= 0)
      j[{static_cast<std::size_t>(t.branches[i].parent), t.branches[i].parent_node}].push_back(i);
  return j;
}

// Same seed -> identical .sylt bytes; another seed -> a different tree.
TEST(WeberPenn, DeterministicPerSeed) {
  const Preset p = busy_preset();
  const std::string a = tree::encode_sylt(make(p, 7));
  EXPECT_EQ(a, tree::encode_sylt(make(p, 7)));
  EXPECT_NE(a, tree::encode_sylt(make(p, 8)));
}

// The generated tree satisfies every model invariant and has all levels and leaves.
TEST(WeberPenn, ProducesValidTree) {
  const tree::Tree t = make(busy_preset(), 1);
  EXPECT_TRUE(tree::validate_tree(t).empty());
  std::vector<int> per_level(3, 0);
  bool clone_seen = false;
  for (const auto& b : t.branches) {
    ++per_level.at(b.level);
    clone_seen |= tree::is_clone(t, b) && b.level > 0;
  }
  EXPECT_GE(per_level[0], 2);  // BaseSplits 1: the trunk and its clone
  EXPECT_GT(per_level[1], 20);
  EXPECT_GT(per_level[2], 100);
  EXPECT_TRUE(clone_seen);  // SegSplits on level 1
  EXPECT_EQ(t.leaves.size(), 3000u);
  for (const auto& l : t.leaves) EXPECT_EQ(t.branches[l.branch].level, 2u);
}

// Raising Levels leaves the lower levels bit-identical: from n to n + 1, every branch of level
// <= n - 2 is unchanged; the level n - 1 branches are the same branches (index, level, parent),
// and those growing from level n - 2 keep their junction and first node exactly (they only gain
// the junctions of their new children, which a clone of theirs sees as a moved split point).
TEST(WeberPenn, RaisingLevelsKeepsLowerLevels) {
  Preset p = busy_preset();
  p.level.push_back(p.level.back());  // a fourth level's parameters
  for (int n = 1; n <= 3; ++n) {
    GenerateOptions lo, hi;
    lo.levels = n;
    hi.levels = n + 1;
    const tree::Tree a = make(p, 3, lo), b = make(p, 3, hi);
    std::size_t same = 0, kept = 0;
    for (std::size_t i = 0; i < a.branches.size(); ++i) {
      ASSERT_LT(i, b.branches.size());
      const auto& x = a.branches[i];
      const auto& y = b.branches[i];
      ASSERT_EQ(x.level, y.level);
      ASSERT_EQ(x.parent, y.parent);
      if (static_cast<int>(x.level) <= n - 2) {
        EXPECT_EQ(x, y) << "n=" << n << " branch " << i;
        ++same;
      } else if (x.parent < 0 ||
                 static_cast<int>(a.branches[static_cast<std::size_t>(x.parent)].level) <= n - 2) {
        EXPECT_EQ(x.parent_node, y.parent_node);
        EXPECT_EQ(x.nodes.front(), y.nodes.front());
        ++kept;
      }
    }
    // b has exactly a's branches plus the new level.
    std::size_t extra = 0;
    for (std::size_t i = a.branches.size(); i < b.branches.size(); ++i) {
      EXPECT_EQ(static_cast<int>(b.branches[i].level), n);
      ++extra;
    }
    EXPECT_GT(extra, 0u) << n;
    if (n >= 2) {
      EXPECT_GT(same, 0u);
    }
    EXPECT_GT(kept, 0u);
  }
}

// da Vinci at every split and attachment: r_k^E = r_{k+1}^E + Σ r_child^E to 1e-6 relative.
TEST(WeberPenn, DaVinciAtEveryJunction) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const Preset p = busy_preset();
    GenerateOptions o;
    o.max_node_spacing = 0.3;
    const tree::Tree t = make(p, seed, o);
    const double e = p.tree_shape_exponent;
    std::size_t checked = 0;
    for (const auto& [key, children] : junctions(t)) {
      const auto& parent = t.branches[key.first];
      ASSERT_LT(key.second + 1, parent.nodes.size()) << "a junction is never a branch tip";
      const double before = std::pow(parent.nodes[key.second].radius, e);
      double after = std::pow(parent.nodes[key.second + 1].radius, e);
      for (std::size_t c : children) after += std::pow(t.branches[c].nodes.front().radius, e);
      ASSERT_GT(before, 0);
      EXPECT_NEAR(after / before, 1.0, 1e-6) << "branch " << key.first << " node " << key.second;
      ++checked;
    }
    EXPECT_GT(checked, 200u);
  }
}

// Murray's exact per-branch angles at every junction with one child, with all angle noise off:
// the continuation bends by x, the child leaves at y, on opposite sides of the incoming axis;
// at a two-way split both members bend by the equal-split angle.
TEST(WeberPenn, MurrayAnglesAtJunctions) {
  const Preset p = exact_preset();
  const tree::Tree t = make(p, 5);
  std::size_t laterals = 0, splits = 0;
  for (const auto& [key, children] : junctions(t)) {
    if (children.size() != 1 || key.second == 0) continue;
    const auto& par = t.branches[key.first];
    const Vec3 pk = par.nodes[key.second].position;
    const Vec3 in = pk - par.nodes[key.second - 1].position;
    const Vec3 out = par.nodes[key.second + 1].position - pk;
    const auto& child = t.branches[children[0]];
    const Vec3 cd = child.nodes.front().position - pk;
    const MurrayAngles m = murray_angles(par.nodes[key.second].radius, par.nodes[key.second + 1].radius,
                                         child.nodes.front().radius);
    EXPECT_NEAR(angle(in, out), m.primary, 1e-6);
    EXPECT_NEAR(angle(in, cd), m.secondary, 1e-6);
    // Coplanar, on opposite sides of the incoming axis.
    const Vec3 a = tree::cross(in, out), b = tree::cross(in, cd);
    if (tree::length(a) > 1e-9) {
      EXPECT_NEAR(angle(a, b), std::numbers::pi, 1e-6);
    }
    if (tree::is_clone(t, child)) {
      ++splits;
      EXPECT_NEAR(m.primary, m.secondary, 1e-9);
      EXPECT_NEAR(m.primary, clone_deviation(p.tree_shape_exponent, 2), 1e-9);
    } else {
      ++laterals;
    }
  }
  EXPECT_GT(laterals, 100u);
  EXPECT_GT(splits, 3u);
}

// Intermediate nodes: one child radius before and after the attachment; the prepended node is
// skipped (the previous node takes its role) when it would be within 10 % of a segment of it.
TEST(WeberPenn, IntermediateNodesAndSkipRule) {
  Preset p;
  p.levels = 2;
  p.scale = 10;
  p.base_size = 0;
  p.ratio = 0.02;
  p.flare = 0;
  LevelParams trunk;
  trunk.curve_res = 1;  // one segment: nodes 0 and 10 m, plus what the attachments add
  LevelParams l1;
  l1.branches = 5;  // at s = 1, 3, 5, 7, 9 m
  l1.length = 0.3;
  l1.curve_res = 2;
  l1.branch_ratio = 0.5;
  p.level = {trunk, l1};
  const tree::Tree t = make(p, 1);
  const auto& trunk_b = t.branches[0];
  ASSERT_EQ(t.branches.size(), 6u);
  // Children 2..5: prepended node = junction, then the appended node 2 r_est further.
  for (std::size_t c = 2; c <= 5; ++c) {
    const auto k = t.branches[c].parent_node;
    const double r_child = t.branches[c].nodes.front().radius;
    const double gap = tree::length(trunk_b.nodes[k + 1].position - trunk_b.nodes[k].position);
    EXPECT_NEAR(gap, 2 * r_child, 0.05 * r_child) << c;
    double from_base = 0;  // arc length: the trunk bends at every junction (primary deviation)
    for (std::uint32_t i = 0; i < k; ++i)
      from_base += tree::length(trunk_b.nodes[i + 1].position - trunk_b.nodes[i].position);
    EXPECT_NEAR(from_base, 2.0 * static_cast<double>(c) - 1 - r_child, 0.05 * r_child + 1e-9) << c;
  }
  // Nodes: base, junction 1 = base, appended, then (prepended = junction, appended) x 4, tip.
  EXPECT_EQ(trunk_b.nodes.size(), 2u + 1u + 2u * 4u);
  // Child 1 attaches at 1 m, whose prepended node (1 m − r) is within 10 % of the 10 m segment
  // of node 0: node 0 is its junction.
  EXPECT_EQ(t.branches[1].parent_node, 0u);
  // The lateral's first node is (1 + S) r_parent from the parent's axis (eq. 3.5).
  const auto& c3 = t.branches[3];
  const Vec3 j = trunk_b.nodes[c3.parent_node].position;
  const double r_parent = trunk_b.nodes[c3.parent_node].radius;
  const Vec3 d = c3.nodes.front().position - j;
  const Vec3 axis =
      tree::normalized(trunk_b.nodes[c3.parent_node].position - trunk_b.nodes[c3.parent_node - 1].position);
  EXPECT_NEAR(tree::length(d - axis * tree::dot(d, axis)), 1.5 * r_parent, 1e-9);
}

// No skeleton segment is longer than max_node_spacing.
TEST(WeberPenn, MaxNodeSpacing) {
  GenerateOptions o;
  o.max_node_spacing = 0.2;
  const tree::Tree t = make(busy_preset(), 2, o);
  std::size_t nodes = 0;
  for (const auto& b : t.branches)
    for (std::size_t k = 1; k < b.nodes.size(); ++k) {
      EXPECT_LE(tree::length(b.nodes[k].position - b.nodes[k - 1].position), 0.2 + 1e-9);
      ++nodes;
    }
  const tree::Tree coarse = make(busy_preset(), 2);
  std::size_t coarse_nodes = 0;
  for (const auto& b : coarse.branches) coarse_nodes += b.nodes.size() - 1;
  EXPECT_GT(nodes, coarse_nodes);
}

// Frames along every generated branch are orthonormal (the mesh stage relies on it).
TEST(WeberPenn, FramesOnGeneratedTree) {
  const tree::Tree t = make(busy_preset(), 4);
  const auto frames = tree::compute_tree_frames(t);
  for (const auto& fs : frames)
    for (const auto& f : fs) {
      ASSERT_NEAR(tree::length(f.t), 1, 1e-9);
      ASSERT_NEAR(tree::dot(f.t, f.n), 0, 1e-9);
      ASSERT_NEAR(tree::length(tree::cross(f.t, f.n) - f.b), 0, 1e-9);
    }
}

// Conifer foliage: needles instead of leaves, on the last level, pointing away from the axis.
TEST(WeberPenn, NeedlesForConifers) {
  Preset p = busy_preset();
  p.foliage = Foliage::kNeedles;
  p.leaf_scale = 0.02;
  p.leaf_scale_x = 0.05;
  const tree::Tree t = make(p, 1);
  EXPECT_TRUE(t.leaves.empty());
  ASSERT_EQ(t.needles.size(), 3000u);
  for (const auto& n : t.needles) {
    EXPECT_EQ(t.branches[n.branch].level, 2u);
    EXPECT_NEAR(tree::length(tree::to_double(n.tip) - tree::to_double(n.base)), 0.02, 0.0031);
  }
}

// Leaf variants use all four atlas quadrants; leaf frames are orthonormal.
TEST(WeberPenn, LeavesUseAllVariants) {
  const tree::Tree t = make(busy_preset(), 1);
  int seen[4] = {};
  for (const auto& l : t.leaves) {
    ++seen[l.variant];
    EXPECT_NEAR(tree::dot(tree::to_double(l.direction), tree::to_double(l.normal)), 0, 1e-5);
  }
  for (int v : seen) EXPECT_GT(v, 500);
}

TEST(WeberPenn, NodeBudget) {
  GenerateOptions o;
  o.max_nodes = 1000;
  EXPECT_THROW(make(busy_preset(), 1, o), std::length_error);
}

TEST(WeberPenn, RejectsBadPreset) {
  Preset p = busy_preset();
  p.level[1].branch_ratio = 0;
  try {
    make(p, 1);
    FAIL();
  } catch (const PresetError& e) {
    EXPECT_EQ(e.key(), "levels[1].BranchRatio");
    EXPECT_STREQ(e.what(), "levels[1].BranchRatio must be in (0, 1]");
  }
}

// Clumps: the laterals gather into `Clumps` groups along the parent's child zone less its bare
// ClumpBase fraction, each spread over ClumpSize of its share and centred on it (25 children in 3
// groups: 9, 8, 8);
// the per-child draws are the same as without clumps, so with a cylindrical shape ratio (length
// independent of position) every lateral keeps its length exactly.
TEST(WeberPenn, ClumpsGatherLateralsIntoGroups) {
  Preset p = exact_preset();
  p.shape = 3;
  p.levels = 2;
  p.level[1].seg_splits = 0;
  Preset even = p;
  p.level[1].clumps = 3;
  p.level[1].clump_size = 0.2;
  p.level[1].clump_base = 0.25;
  const tree::Tree t = make(p, 5), e = make(even, 5);
  const tree::Branch& trunk = t.branches[0];
  std::vector<double> arc(trunk.nodes.size(), 0.0);
  for (std::size_t k = 1; k < arc.size(); ++k)
    arc[k] = arc[k - 1] + tree::length(trunk.nodes[k].position - trunk.nodes[k - 1].position);
  const double L = arc.back(), lo = p.base_size * L + 0.25 * (1 - p.base_size) * L, share = (L - lo) / 3;
  const double tolerance = 0.1 * L / p.level[0].curve_res + trunk.nodes[0].radius;  // prepended node
  std::vector<int> per_group(3, 0);
  std::vector<double> lengths, even_lengths;
  auto branch_length = [](const tree::Branch& b) {
    double l = 0;
    for (std::size_t k = 1; k < b.nodes.size(); ++k)
      l += tree::length(b.nodes[k].position - b.nodes[k - 1].position);
    return l;
  };
  for (const tree::Branch& b : t.branches) {
    if (b.parent != 0) continue;
    const double s = arc[b.parent_node];
    const int g = std::clamp(static_cast<int>((s - lo) / share), 0, 2);
    const double centre = lo + (g + 0.5) * share;
    EXPECT_GE(s, centre - 0.1 * share - tolerance) << "group " << g;
    EXPECT_LE(s, centre + 0.1 * share) << "group " << g;
    ++per_group[g];
    lengths.push_back(branch_length(b));
  }
  EXPECT_EQ(per_group, (std::vector<int>{9, 8, 8}));
  for (const tree::Branch& b : e.branches)
    if (b.parent == 0) even_lengths.push_back(branch_length(b));
  ASSERT_EQ(lengths.size(), even_lengths.size());
  for (std::size_t i = 0; i < lengths.size(); ++i) EXPECT_NEAR(lengths[i], even_lengths[i], 1e-9) << i;
  // Without clumps the same laterals spread over the whole zone: the bare base and the middle of
  // the first gap (between groups 0 and 1) have children within a tenth of a share of them.
  int in_gap = 0, in_base = 0;
  for (const tree::Branch& b : e.branches) {
    if (b.parent != 0) continue;
    double s = 0;
    for (std::uint32_t k = 1; k <= b.parent_node; ++k)
      s += tree::length(e.branches[0].nodes[k].position - e.branches[0].nodes[k - 1].position);
    if (std::abs(s - (lo + share)) < 0.1 * share) ++in_gap;
    if (s < lo - tolerance) ++in_base;
  }
  EXPECT_GE(in_gap, 1);
  EXPECT_GE(in_base, 3);
  EXPECT_TRUE(tree::validate_tree(t).empty());
}

// The message make() throws for `p` ("(no error)" when it generates).
std::string preset_error(const Preset& p) {
  try {
    make(p, 1);
  } catch (const PresetError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(WeberPenn, RejectsBadClumps) {
  Preset p = busy_preset();
  p.level[2].clumps = 101;
  EXPECT_EQ(preset_error(p), "levels[2].Clumps must be 0..100");
  p.level[2].clumps = 4;
  p.level[2].clump_size = 0;
  EXPECT_EQ(preset_error(p), "levels[2].ClumpSize must be in (0, 1]");
  p.level[2].clump_size = 0.3;
  p.level[2].clump_base = 1;
  EXPECT_EQ(preset_error(p), "levels[2].ClumpBase must be in [0, 1)");
}

// Hem: with AttractionUp < 0 the last level hangs; every last-level branch that would reach
// below its hem (Hem x the trunk's length x (1 + HemV u)) ends there, at the crossing, and the
// hems spread over the HemV band. The hem's draws come after every growth draw, so the tree is
// the one without a hem but for where the hanging branches end: every other branch is
// bit-identical, and a cut branch is a prefix of its uncut self ending on its segment.
TEST(WeberPenn, HemEndsTheHangingLastLevelAtItsHeight) {
  Preset p = busy_preset();
  p.attraction_up = -3;
  Preset none = p;
  p.hem = 0.4;
  p.hem_v = 0.2;
  const tree::Tree t = make(p, 3), u = make(none, 3);
  ASSERT_TRUE(tree::validate_tree(t).empty());
  ASSERT_EQ(t.branches.size(), u.branches.size());
  double trunk = 0;
  for (std::size_t k = 1; k < t.branches[0].nodes.size(); ++k)
    trunk += tree::length(t.branches[0].nodes[k].position - t.branches[0].nodes[k - 1].position);
  const double lo = 0.4 * trunk * 0.8, hi = 0.4 * trunk * 1.2;
  int cut = 0, uncut_reaching = 0;
  double cut_min = 1e9, cut_max = -1e9;
  for (std::size_t i = 0; i < t.branches.size(); ++i) {
    const tree::Branch &b = t.branches[i], &w = u.branches[i];
    if (b.level < 2 || b.nodes == w.nodes) {
      EXPECT_EQ(b.nodes, w.nodes) << i;
      double lowest = 1e9;
      for (const tree::Node& n : b.nodes) lowest = std::min(lowest, n.position.y);
      if (b.level == 2 && b.nodes.front().position.y > hi && lowest < lo) ++uncut_reaching;
      continue;
    }
    ASSERT_LE(b.nodes.size(), w.nodes.size()) << i;
    const std::size_t n = b.nodes.size();
    for (std::size_t k = 0; k + 1 < n; ++k) EXPECT_EQ(b.nodes[k], w.nodes[k]) << i << " node " << k;
    // Starting below every hem (level 2 has no splits here): it ends at its second node.
    if (b.nodes.front().position.y < lo) {
      EXPECT_EQ(n, 2u) << i;
      EXPECT_EQ(b.nodes[1], w.nodes[1]) << i;
      continue;
    }
    if (b.nodes.front().position.y <= hi) continue;  // starts inside the band
    // The end lies on the uncut branch's segment n-2 .. n-1, within the hem band, below every
    // other node; the uncut branch goes on below it.
    const Vec3 a = w.nodes[n - 2].position, c = w.nodes[n - 1].position, e = b.nodes.back().position;
    EXPECT_LT(tree::length(tree::cross(c - a, e - a)), 1e-9 * (1 + tree::length(c - a))) << i;
    EXPECT_LE(tree::dot(e - a, c - a), tree::dot(c - a, c - a) + 1e-12) << i;
    EXPECT_GE(e.y, lo - 1e-9) << i;
    EXPECT_LE(e.y, hi + 1e-9) << i;
    for (std::size_t k = 0; k + 1 < n; ++k) EXPECT_GT(b.nodes[k].position.y, e.y) << i;
    EXPECT_LT(w.nodes.back().position.y, e.y) << i;
    ++cut;
    cut_min = std::min(cut_min, e.y);
    cut_max = std::max(cut_max, e.y);
  }
  std::printf("[ hem      ] %d branches cut, ends %.2f..%.2f m in the band %.2f..%.2f m\n", cut, cut_min,
              cut_max, lo, hi);
  EXPECT_GE(cut, 15);
  EXPECT_EQ(uncut_reaching, 0);  // nothing that starts above the band hangs through it uncut
  EXPECT_LT(cut_min, lo + 0.25 * (hi - lo));
  EXPECT_GT(cut_max, hi - 0.25 * (hi - lo));
}

TEST(WeberPenn, RejectsBadHem) {
  Preset p = busy_preset();
  p.hem = 1;
  EXPECT_EQ(preset_error(p), "Hem must be in [0, 1)");
  p.hem = 0.3;
  p.hem_v = -0.1;
  EXPECT_EQ(preset_error(p), "HemV must be in [0, 1)");
}

// TrunkUp: after each node's turns a level-0 branch turns back towards the vertical by TrunkUp x
// its declination. At 1 the trunk's axis is the vertical through its base, node for node, and a
// trunk clone rises vertically from its stub; at 0.5 the trunk strays less than without
// (the primary deviations of 25 laterals, the Curve and the split add up to a lean); it draws
// nothing, so the tree has the same branches.
TEST(WeberPenn, TrunkUpKeepsTheLeaderVertical) {
  Preset p = busy_preset();
  auto stray = [](const tree::Branch& b, std::size_t from) {
    double d = 0;
    const Vec3 o = b.nodes[from].position;
    for (std::size_t k = from; k < b.nodes.size(); ++k)
      d = std::max(d, std::hypot(b.nodes[k].position.x - o.x, b.nodes[k].position.z - o.z));
    return d;
  };
  const tree::Tree free = make(p, 2);
  p.trunk_up = 0.5;
  const tree::Tree half = make(p, 2);
  p.trunk_up = 1;
  const tree::Tree up = make(p, 2);
  ASSERT_TRUE(tree::validate_tree(up).empty());
  ASSERT_EQ(up.branches.size(), free.branches.size());
  const double h = up.branches[0].nodes.back().position.y;
  EXPECT_LT(stray(up.branches[0], 0), 1e-9 * h);
  int clones = 0;
  for (const tree::Branch& b : up.branches) {
    if (b.level != 0 || b.parent < 0) continue;
    ++clones;
    EXPECT_LT(stray(b, 0), 1e-9 * h);
    // Its first node (the stub) lies off the trunk's vertical, along the split's angle.
    const Vec3 o = up.branches[0].nodes[0].position, s0 = b.nodes[0].position;
    EXPECT_GT(std::hypot(s0.x - o.x, s0.z - o.z), 1e-3);
  }
  EXPECT_GE(clones, 1);
  EXPECT_GT(stray(free.branches[0], 0), 0.02 * h);
  EXPECT_LT(stray(half.branches[0], 0), 0.5 * stray(free.branches[0], 0));
}

TEST(WeberPenn, RejectsBadTrunkUp) {
  Preset p = busy_preset();
  p.trunk_up = 1.5;
  EXPECT_EQ(preset_error(p), "TrunkUp must be in [0, 1]");
}

// ShapeFloor remaps W&P's shape ratios 0-2 (0.2 + 0.8 f) to F + (1 - F) f for level-1 lengths;
// nothing else changes (no draw, same positions). At 1 every level-1 branch (LengthV 0) is
// Length x the trunk's length; at 0 each is shorter than W&P's, the topmost far shorter.
TEST(WeberPenn, ShapeFloorSetsTheCrownsEnds) {
  Preset p = exact_preset();
  p.shape = 0;
  p.levels = 2;
  p.level[0].seg_splits = 0;
  p.level[1].seg_splits = 0;
  p.level[1].length_v = 0;
  const tree::Tree wp = make(p, 4);
  p.shape_floor = 1;
  const tree::Tree one = make(p, 4);
  p.shape_floor = 0;
  const tree::Tree zero = make(p, 4);
  auto length = [](const tree::Branch& b) {
    double l = 0;
    for (std::size_t k = 1; k < b.nodes.size(); ++k)
      l += tree::length(b.nodes[k].position - b.nodes[k - 1].position);
    return l;
  };
  const double trunk = length(wp.branches[0]);
  ASSERT_EQ(one.branches.size(), wp.branches.size());
  ASSERT_EQ(zero.branches.size(), wp.branches.size());
  double top_ratio = 1, top_y = -1;
  for (std::size_t i = 1; i < wp.branches.size(); ++i) {
    EXPECT_NEAR(length(one.branches[i]), p.level[1].length * trunk, 1e-9 * trunk) << i;
    EXPECT_EQ(one.branches[i].parent_node, wp.branches[i].parent_node) << i;
    EXPECT_LT(length(zero.branches[i]), length(wp.branches[i])) << i;
    if (wp.branches[i].nodes[0].position.y > top_y) {
      top_y = wp.branches[i].nodes[0].position.y;
      top_ratio = length(zero.branches[i]) / length(wp.branches[i]);
    }
  }
  EXPECT_LT(top_ratio, 0.5);
  p.shape = 3;
  p.shape_floor = 0.1;
  EXPECT_EQ(preset_error(p), "ShapeFloor must be 0.2 (W&P's) unless Shape is 0, 1 or 2");
  p.shape = 0;
  p.shape_floor = 1.5;
  EXPECT_EQ(preset_error(p), "ShapeFloor must be in [0, 1]");
}

// Pendulous: with AttractionUp < 0, W&P's turn (proportional to the declination) leaves a
// shoot pointing up standing; at Pendulous 1 the pull is proportional to the angle from the
// downward vertical, so every level-2 branch of a strongly drooping tree ends pointing down
// (within 60 degrees), where W&P's leaves some standing. No draw: levels 0-1 are unchanged.
TEST(WeberPenn, PendulousFlopsUpwardShootsOver) {
  Preset p = busy_preset();
  p.attraction_up = -4;
  p.level[2].curve_res = 6;
  p.level[2].curve = p.level[2].curve_v = p.level[2].curve_back = 0;
  const tree::Tree wp = make(p, 5);
  p.pendulous = 1;
  const tree::Tree pd = make(p, 5);
  ASSERT_TRUE(tree::validate_tree(pd).empty());
  ASSERT_EQ(pd.branches.size(), wp.branches.size());
  auto tip_dir_y = [](const tree::Branch& b) {
    return tree::normalized(b.nodes.back().position - b.nodes[b.nodes.size() - 2].position).y;
  };
  int up_wp = 0, up_pd = 0, n = 0;
  for (std::size_t i = 0; i < pd.branches.size(); ++i) {
    if (pd.branches[i].level != 2) {
      if (pd.branches[i].level < 2) {
        EXPECT_EQ(pd.branches[i].nodes, wp.branches[i].nodes) << i;
      }
      continue;
    }
    ++n;
    up_wp += tip_dir_y(wp.branches[i]) > -0.5;
    up_pd += tip_dir_y(pd.branches[i]) > -0.5;
  }
  std::printf(
      "[ pendulous] %d level-2 branches; tips not pointing down (> 60 deg from it): W&P %d, Pendulous %d\n",
      n, up_wp, up_pd);
  EXPECT_GT(up_wp, 0);  // W&P leaves some standing
  EXPECT_EQ(up_pd, 0);  // Pendulous turns every one down
  p.pendulous = 1.5;
  EXPECT_EQ(preset_error(p), "Pendulous must be in [0, 1]");
  p.pendulous = 0.5;
  p.attraction_up = 0.5;
  EXPECT_EQ(preset_error(p), "Pendulous must be 0 unless AttractionUp < 0");
}

TEST(WeberPenn, ShapeRatio) {
  EXPECT_DOUBLE_EQ(shape_ratio(0, 1), 1.0);
  EXPECT_DOUBLE_EQ(shape_ratio(0, 0), 0.2);
  EXPECT_NEAR(shape_ratio(1, 0.5), 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(shape_ratio(3, 0.3), 1.0);
  EXPECT_NEAR(shape_ratio(5, 0.7), 1.0, 1e-15);
}

}  // namespace
}  // namespace sylva::generate
