// Tests of the pure lod core: Zhang et al. 2017 §4–§6 and FSA/VDF leaf collapse.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>

#include "libs/tree/tree.h"
#include "stages/lod/chain.h"
#include "stages/lod/foliage.h"
#include "stages/lod/internodes.h"
#include "stages/lod/needles.h"
#include "stages/lod/polygonize.h"
#include "stages/lod/ribbons.h"
#include "stages/lod/tests/test_trees.h"
#include "stages/lod/topology.h"

namespace sylva::lod {
namespace {

using tree::Vec3;

double P(int i) { return 1 - std::cos(std::numbers::pi / i); }

// Eq. (9)/(11): the edge function's steps at P_i = 1 - cos(pi/i) and its two extensions.
TEST(EdgeFunction, StepsOfEquation11) {
  EXPECT_EQ(edge_count(0.0, 12), 12);
  EXPECT_EQ(edge_count(P(12) * 0.99, 12), 12);  // rho < P_H: H
  EXPECT_EQ(edge_count(P(12), 12), 12);
  EXPECT_EQ(edge_count(P(7), 12), 7);  // the 7-gon's error is exactly P_7
  EXPECT_EQ(edge_count(P(7) * 0.999, 12), 8);
  EXPECT_EQ(edge_count(P(4), 12), 4);
  EXPECT_EQ(edge_count(0.49, 12), 4);
  EXPECT_EQ(edge_count(0.5, 12), 3);  // 0.5 <= rho < 2: a prism of 3
  EXPECT_EQ(edge_count(1.99, 12), 3);
  EXPECT_EQ(edge_count(2.0, 12), 1);       // rho >= 2: a line
  EXPECT_EQ(edge_count(INFINITY, 12), 1);  // R = 0
  EXPECT_DOUBLE_EQ(line_alpha(4.0), 0.5);  // eq. (12)
  EXPECT_DOUBLE_EQ(line_alpha(1.0), 1.0);
  // The drawn alpha of eq. 12's lines: libs/lodmodel/tests (LodModel.DrawnLineAlpha).
  // Every h-gon chosen keeps its polygonisation error under E3 = rho R.
  for (double rho = 0.001; rho < 2; rho *= 1.1) {
    const int h = edge_count(rho, 1000);
    EXPECT_LE(P(h), rho + 1e-12) << rho;
  }
}

tree::Tree one_branch(std::vector<Vec3> ps, std::vector<double> rs) {
  tree::Tree t;
  tree::Branch b;
  for (std::size_t i = 0; i < ps.size(); ++i) b.nodes.push_back({ps[i], rs[i]});
  t.branches.push_back(b);
  return t;
}

// A straight branch of three nodes 1 m apart along +Y with `radii`, polygonized with every node
// kept at E3 = 0.04 m (up to 12 ring edges), `extra_alpha12` carried onto its nodes.
BranchGeometry thin_branch(std::vector<double> radii, std::span<const double> extra_alpha12 = {}) {
  const auto sk = build_skeletons(one_branch({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}}, std::move(radii)));
  const std::uint32_t kept[] = {0, 1, 2};
  BranchGeometry g;
  polygonize_branch(sk[0].g, kept, 0.04, 12, g, extra_alpha12);
  return g;
}

// A straight branch with linear taper merges into one internode with zero error.
TEST(InternodeMerging, StraightTaperedBranchMergesCompletely) {
  const auto t = one_branch({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}}, {0.4, 0.3, 0.2, 0.1});
  const auto sk = build_skeletons(t);
  const MergeError e = merge_error(sk[0].g, 0, 3);
  EXPECT_NEAR(e.phi, 0, 1e-12);
  EXPECT_NEAR(e.varphi, 0, 1e-12);
  std::vector<std::uint32_t> kept;
  merge_internodes(sk[0].g, {1e-9, 1e-9, 1.0}, kept);
  EXPECT_EQ(kept, (std::vector<std::uint32_t>{0, 3}));
}

// A bent branch: phi is the inner node's distance from the chord at tau (eq. 4, 5), computed
// explicitly; merging happens exactly when E1 reaches it.
TEST(InternodeMerging, PositionalErrorIsEquation4) {
  const auto t = one_branch({{0, 0, 0}, {0.1, 1, 0}, {0, 2, 0}}, {0.01, 0.01, 0.01});
  const auto sk = build_skeletons(t);
  const MergeError e = merge_error(sk[0].g, 0, 2);
  EXPECT_NEAR(e.phi, 0.1, 1e-12);  // tau = 1/2 by symmetry: X = (0,1,0) - (0.1,1,0)
  EXPECT_NEAR(e.torsion, 2 * sk[0].g[1].beta, 1e-15);
  std::vector<std::uint32_t> kept;
  merge_internodes(sk[0].g, {0.0999, 1, 1}, kept);
  EXPECT_EQ(kept.size(), 3u);
  kept.clear();
  merge_internodes(sk[0].g, {0.1001, 1, 1}, kept);
  EXPECT_EQ(kept.size(), 2u);
  // The torsion limit alone blocks it.
  kept.clear();
  merge_internodes(sk[0].g, {1, 1, 2 * sk[0].g[1].beta * 0.99}, kept);
  EXPECT_EQ(kept.size(), 3u);
}

// Merging on long chains (issue 15, item 13): a 40,000-node gently wavy branch merges into
// groups that each meet eq. (3) and the torsion bound (checked with merge_error), the search
// stays near-linear (bench_lod BM_MergeStraightChain: 80k nodes in ~2 ms; it was quadratic,
// 20k nodes 1.6 s), and a cancellation callback stops it from inside the loop.
TEST(InternodeMerging, LongChainGroupsMeetTheBoundsAndCancellationStops) {
  std::vector<Vec3> ps;
  std::vector<double> rs;
  for (int i = 0; i < 40000; ++i) {
    const double y = 0.05 * i;
    ps.push_back({0.004 * std::sin(y * 0.9), y, 0.003 * std::cos(y * 0.37)});
    rs.push_back(0.05);
  }
  const auto sk = build_skeletons(one_branch(ps, rs));
  const MergeLimits limits{0.002, 0.002, 1.0};
  std::vector<std::uint32_t> kept;
  merge_internodes(sk[0].g, limits, kept);
  ASSERT_GE(kept.size(), 3u);
  EXPECT_LT(kept.size(), 40000u / 4);  // it does merge
  EXPECT_EQ(kept.front(), 0u);
  EXPECT_EQ(kept.back(), 39999u);
  for (std::size_t i = 0; i + 1 < kept.size(); ++i) {
    const MergeError e = merge_error(sk[0].g, kept[i], kept[i + 1]);
    ASSERT_LE(e.phi, limits.e1) << "group " << i;
    ASSERT_LE(e.varphi, limits.e2) << "group " << i;
    ASSERT_LE(e.torsion, limits.gamma) << "group " << i;
  }
  int calls = 0;
  kept.clear();
  EXPECT_THROW(merge_internodes(sk[0].g, limits, kept,
                                [&] {
                                  if (++calls == 3) throw std::runtime_error("cancelled");
                                }),
               std::runtime_error);
  EXPECT_EQ(calls, 3);
}

// Vertex connection cases (ii), (iii) and (i) of §5.1.
TEST(Polygonize, PrismPrismoidAndFanCover) {
  // R = 1, 1, 0.2: E3 = 0.03 gives H = 12 (rho 0.03), 12, then rho 0.15 -> 6.
  const auto t = one_branch({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}}, {1, 1, 0.2, 0.01});
  const auto sk = build_skeletons(t);
  const std::uint32_t kept[] = {0, 1, 2, 3};
  BranchGeometry g;
  polygonize_branch(sk[0].g, kept, 0.03, 12, g);
  EXPECT_EQ(g.ring_edges, (std::vector<int>{12, 12, 6}));
  // prism: 12 quads; prismoid 12 -> 6: d = 6 triangles + f = 6 quads; fan cover: 6 triangles
  // to the line node (rho = 3 at R = 0.01); no line internode after the last node.
  EXPECT_EQ(g.quads, 12u + 6u);
  EXPECT_EQ(g.triangles, 6u + 6u);
  EXPECT_EQ(g.lines, 0u);
  EXPECT_EQ(g.tri_indices.size(), 3 * (2 * g.quads + g.triangles));
  // No sliver: in the prismoid every triangle spans one edge of the 12-gon.
}

// Lines: h = 1 from rho >= 2; three segments per internode with normals 120° apart (§5.5).
TEST(Polygonize, ThinBranchBecomesThreeLinesPerInternode) {
  const BranchGeometry g = thin_branch({0.01, 0.01, 0.01});  // rho = 4
  EXPECT_EQ(g.lines, 6u);
  EXPECT_EQ(g.line_indices.size(), 12u);
  EXPECT_EQ(g.line_positions.size(), 9u * 3);  // 3 vertices per node, shared along the chain
  EXPECT_DOUBLE_EQ(g.level_alpha(), 0.5);      // eq. (12): 2 / 4
  const float* n = g.line_normals.data();
  EXPECT_NEAR(n[0] * n[3] + n[1] * n[4] + n[2] * n[5], -0.5, 1e-6);  // cos 120°
}

// Line alpha per vertex (eq. 12 at each node, not one per level): a tapered thin branch's line
// vertices carry 2 R_k / E3 of their own node, and the output's COLOR_0 alpha is its drawn value.
TEST(Polygonize, LineAlphaIsEquation12AtEachNode) {
  const std::vector<double> radii = {0.01, 0.005, 0.0025};
  const BranchGeometry g = thin_branch(radii);
  ASSERT_EQ(g.line_alpha12.size(), 9u);
  const double want[] = {0.5, 0.25, 0.125};  // 2 R / E3
  for (std::size_t v = 0; v < 9; ++v) EXPECT_NEAR(g.line_alpha12[v], want[v / 3], 1e-7) << v;
  // Decimated coverage carried onto node 1 adds to that node only.
  const double extra[] = {0, 0.3, 0};
  const BranchGeometry h = thin_branch(radii, extra);
  for (std::size_t v = 0; v < 9; ++v) EXPECT_NEAR(h.line_alpha12[v], want[v / 3] + extra[v / 3], 1e-7) << v;
}

// Rings keep the cylinder's mean width: an h-gon of circumradius k R, k = pi / (h sin(pi/h)),
// has perimeter 2 pi R (Cauchy: mean width = perimeter / pi = 2R); its error against the circle
// stays below the inscribed polygon's, so eq. (9)'s choice of h still bounds it by E3.
TEST(Polygonize, RingsKeepTheMeanWidthOfTheCylinder) {
  for (int h = 3; h <= 12; ++h) {
    const double k = ring_factor(h);
    EXPECT_NEAR(2 * h * k * std::sin(std::numbers::pi / h), 2 * std::numbers::pi, 1e-12) << h;
    EXPECT_LT(polygon_error(1.0, h), 1 - std::cos(std::numbers::pi / h)) << h;
    EXPECT_GT(polygon_error(1.0, h), 0) << h;
  }
  EXPECT_NEAR(ring_factor(3), kRibbonCornerFactor, 1e-12);
  // R = 0.1 with E3 = 0.1 (rho = 1): a triangle whose corners lie k R from the axis.
  const auto t = one_branch({{0, 0, 0}, {0, 1, 0}}, {0.1, 0.1});
  const auto sk = build_skeletons(t);
  const std::uint32_t kept[] = {0, 1};
  BranchGeometry g;
  polygonize_branch(sk[0].g, kept, 0.1, 12, g);
  ASSERT_EQ(g.ring_edges, (std::vector<int>{3, 3}));
  for (std::size_t v = 0; v < g.tri_positions.size() / 3; ++v)
    EXPECT_NEAR(std::hypot(g.tri_positions[3 * v], g.tri_positions[3 * v + 2]), ring_factor(3) * 0.1, 1e-6);
}

// Ribbons (ribbons.h): the 6 line segments of a thin two-internode branch (radius 1 cm along
// +Y) become 12 triangles on the same 9 vertices, each corner k R from the axis, every triangle
// counter-clockwise seen from outside (its geometric normal points away from the axis), and the
// prism's mean projected width (perimeter / pi) equals the branch's diameter.
TEST(Ribbons, LinesBecomeOutwardTriangularPrismsOfTheBranchWidth) {
  const BranchGeometry g = thin_branch({0.01, 0.01, 0.01});
  ASSERT_EQ(g.line_radii.size(), g.line_positions.size() / 3);
  const Ribbons r = line_ribbons(g);
  EXPECT_EQ(r.triangles, 2 * g.lines);
  EXPECT_EQ(r.indices.size(), 3 * r.triangles);
  ASSERT_EQ(r.positions.size(), g.line_positions.size());
  for (std::size_t v = 0; v < r.positions.size() / 3; ++v)
    EXPECT_NEAR(std::hypot(r.positions[3 * v], r.positions[3 * v + 2]), kRibbonCornerFactor * 0.01, 1e-6);
  for (std::size_t k = 0; k < r.indices.size(); k += 3) {
    Vec3 p[3];
    for (int c = 0; c < 3; ++c)
      p[c] = {r.positions[3 * r.indices[k + c]], r.positions[3 * r.indices[k + c] + 1],
              r.positions[3 * r.indices[k + c] + 2]};
    const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    const Vec3 centre = (p[0] + p[1] + p[2]) * (1.0 / 3);
    EXPECT_GT(n.x * centre.x + n.z * centre.z, 0) << "triangle " << k / 3 << " faces inward";
  }
  const double side = std::sqrt(3.0) * kRibbonCornerFactor * 0.01;
  EXPECT_NEAR(3 * side / std::numbers::pi, 2 * 0.01, 1e-9);
}

// Zhang Figure 7: a helix cylinder (radius 0.1 m on a helix of radius 1 m, pitch 2 m, 64 nodes a
// turn, 2 turns) under rising epsilon reproduces the prism edge counts 12, 6, 4, 3, 3 with the
// quad count falling. With E3 = epsilon and R = 0.1: epsilon = 3.5, 15, 30, 60, 150 mm give
// rho = 0.035 (12-gon), 0.15 (6), 0.30 (4), 0.6 (3), 1.5 (3).
TEST(Chain, HelixReproducesFigure7) {
  const tree::Tree t = test::helix(1.0, 2.0, 2, 64, 0.1);
  ChainOptions o;
  o.errors = {0.0035, 0.015, 0.03, 0.06, 0.15};
  const auto levels = build_chain(t, o);
  ASSERT_EQ(levels.size(), 5u);
  const int expected_edges[] = {12, 6, 4, 3, 3};
  std::size_t previous_quads = SIZE_MAX;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Level& l = levels[i];
    for (int h : l.branches.ring_edges) EXPECT_EQ(h, expected_edges[i]) << "level " << i;
    EXPECT_EQ(l.counts.triangles, 0u);  // a prism everywhere: constant radius
    EXPECT_EQ(l.counts.quads, l.counts.internodes * static_cast<std::size_t>(expected_edges[i]));
    EXPECT_LT(l.counts.quads, previous_quads) << "level " << i;
    previous_quads = l.counts.quads;
  }
  // Merging does real work at the coarse end (64 nodes a turn -> far fewer internodes).
  EXPECT_LT(levels.back().counts.internodes, 128u / 3);
}

// The error vocabulary of docs/lod-model.md: epsilon = delta s(d) at the switch distance.
TEST(Chain, SwitchDistanceMatchesPixelError) {
  ChainOptions o;
  o.levels = 6;
  const auto specs = plan_levels(o);
  ASSERT_EQ(specs.size(), 6u);
  EXPECT_NEAR(specs.front().epsilon, o.min_error, 1e-15);
  EXPECT_NEAR(specs.back().epsilon, 0.22, 1e-12);
  for (const auto& s : specs)
    EXPECT_NEAR(s.delta * lodmodel::pixel_size(o.camera, s.switch_distance), s.epsilon, 1e-12);
  o.levels = 9;
  EXPECT_THROW(plan_levels(o), std::invalid_argument);
  o.errors = {0.1, 0.05};
  EXPECT_THROW(plan_levels(o), std::invalid_argument);
}

// Zhang Figure 8: a holly-like tree 2.2 m tall seen at 36 m; the epsilon ladder 0.092, 3.87,
// 10.8, 18.8, 39 cm gives strictly falling primitive counts, with lines at the coarse end.
TEST(Chain, HollyLadderOfFigure8) {
  const auto preset = std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species/holly.yaml";
  const tree::Tree t = test::scaled_to_height(test::species_tree(preset, "young"), 2.2);
  ChainOptions o;
  o.errors = {0.00092, 0.0387, 0.108, 0.188, 0.39};
  const auto levels = build_chain(t, o);
  std::size_t previous = SIZE_MAX;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const LevelCounts& c = levels[i].counts;
    const std::size_t branch_prims = c.quads + c.triangles + c.lines;
    std::printf(
        "holly eps %.4f m: quads %zu triangles %zu lines %zu leaves %zu branches %zu internodes %zu\n",
        levels[i].spec.epsilon, c.quads, c.triangles, c.lines, c.leaves, c.branches, c.internodes);
    EXPECT_LT(branch_prims, previous) << "level " << i;
    EXPECT_LT(c.total(), i == 0 ? SIZE_MAX : levels[i - 1].counts.total());
    previous = branch_prims;
  }
  EXPECT_GT(levels.front().counts.quads, 0u);
  EXPECT_GT(levels.back().counts.lines, 0u);
  EXPECT_EQ(levels.back().counts.quads, 0u);
}

// §5.3: a twig lying inside its bearer has A = its own reach; deleted once E4 covers it, and a
// kept child keeps its bearer (A is monotone towards the root).
TEST(Topology, AccumulatedDistanceDecimatesSubtrees) {
  tree::Tree t = one_branch({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}}, {0.2, 0.2, 0.2});
  tree::Branch c;
  c.parent = 0;
  c.parent_node = 1;
  c.level = 1;
  c.nodes = {{{0.1, 1, 0}, 0.02}, {{0.5, 1, 0}, 0.02}};  // reaches 0.3 + 0.02 beyond the trunk
  t.branches.push_back(c);
  tree::Branch g;
  g.parent = 1;
  g.parent_node = 1;
  g.level = 2;
  g.nodes = {{{0.5, 1, 0}, 0.01}, {{0.5, 1.3, 0}, 0.01}};  // 0.3 - 0.02 + 0.01 beyond its bearer
  t.branches.push_back(g);
  ASSERT_TRUE(tree::validate_tree(t).empty());
  const auto sk = build_skeletons(t);
  const auto h = bearer_distances(sk);
  EXPECT_NEAR(h[1], 0.32, 1e-9);
  EXPECT_NEAR(h[2], 0.29, 1e-9);
  const auto a = accumulated_distances(sk, h);
  EXPECT_NEAR(a[1], 0.61, 1e-9);
  EXPECT_NEAR(a[2], 0.29, 1e-9);
  EXPECT_TRUE(std::isinf(a[0]));
}

// Coverage of decimated branches (topology.h): a subtree's side-on area sum (R_k + R_k+1) L,
// accumulated to its ancestors; carried onto the bearer's kept node nearest the attachment as
// A / (E3 w), w = half of the adjacent internodes, so that node's line covers A more.
TEST(Topology, DecimatedCoverageIsCarriedOntoTheBearersLine) {
  tree::Tree t = one_branch({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}}, {0.02, 0.02, 0.02, 0.02});
  tree::Branch c;
  c.parent = 0;
  c.parent_node = 1;
  c.parent_t = 0.25;  // grows at arc 1.25 m
  c.level = 1;
  c.nodes = {{{0, 1.25, 0.01}, 0.004}, {{0, 1.25, 0.05}, 0.004}};
  t.branches.push_back(c);
  ASSERT_TRUE(tree::validate_tree(t).empty());
  const auto sk = build_skeletons(t);
  EXPECT_NEAR(sk[1].attach_arc, 1.25, 1e-12);
  const auto area = subtree_areas(sk);
  // child: implicit segment (0.01 m) + 0.04 m at radius 0.004 m; trunk: 3 m at 0.02 m, plus the child.
  EXPECT_NEAR(area[1], 0.008 * 0.05, 1e-12);
  EXPECT_NEAR(area[0], 0.04 * 3 + area[1], 1e-12);
  // A twig its cards draw is never lost by a level: its area is not carried.
  const std::vector<char> cards = {0, 1};
  const auto with_cards = subtree_areas(sk, cards);
  EXPECT_EQ(with_cards[1], 0.0);
  EXPECT_NEAR(with_cards[0], 0.04 * 3, 1e-12);
  const std::uint32_t kept[] = {0, 1, 3};  // node 1 stands for (1 + 2) / 2 = 1.5 m
  const std::pair<double, double> deposit[] = {{1.25, area[1]}};
  const auto extra = carried_alpha(sk[0].g, kept, deposit, 0.1);
  ASSERT_EQ(extra.size(), 3u);
  EXPECT_EQ(extra[0], 0.0);
  EXPECT_NEAR(extra[1], area[1] / (0.1 * 1.5), 1e-12);
  EXPECT_EQ(extra[2], 0.0);
  // Through the chain at epsilon = 0.2: the trunk is lines (rho = 10), the child (A(b) = 0.034 m
  // <= E4 = 0.1 m) is decimated, and its area reappears on the trunk's lines.
  ChainOptions o;
  o.errors = {0.2};
  o.foliage = false;
  const std::vector<Level> levels = build_chain(t, o);
  ASSERT_EQ(levels[0].counts.branches, 1u);
  const BranchGeometry& g = levels[0].branches;
  ASSERT_FALSE(g.line_alpha12.empty());
  ChainOptions no_topology = o;
  no_topology.topology = false;
  const std::vector<Level> both = build_chain(t, no_topology);
  ASSERT_EQ(both[0].counts.branches, 2u);
  // Alpha times E3 times the length a vertex stands for = side-on area: the level keeps it.
  auto covered = [](const BranchGeometry& b, double e3) {
    double sum = 0;
    for (std::size_t s = 0; s + 1 < b.line_indices.size(); s += 2) {
      const std::uint32_t a = b.line_indices[s], z = b.line_indices[s + 1];
      const double len = std::hypot(b.line_positions[3 * z] - b.line_positions[3 * a],
                                    b.line_positions[3 * z + 1] - b.line_positions[3 * a + 1],
                                    b.line_positions[3 * z + 2] - b.line_positions[3 * a + 2]);
      sum += 0.5 * (b.line_alpha12[a] + b.line_alpha12[z]) * e3 * len / 3;  // three lines per internode
    }
    return sum;
  };
  EXPECT_NEAR(covered(g, 0.2), covered(both[0].branches, 0.2), 1e-6);
  EXPECT_GT(covered(g, 0.2), 0.04 * 3 - 1e-6);
}

std::vector<tree::Leaf> leaf_row(int n) {
  std::vector<tree::Leaf> leaves;
  for (int i = 0; i < n; ++i) {
    tree::Leaf l;
    l.position = {static_cast<float>(i) * 0.1f, 1.f, static_cast<float>(i % 3) * 0.05f};
    l.direction = {0, 0, 1};
    l.normal = {0, 1, 0};
    l.length = 0.06f;
    l.width = 0.03f;
    l.variant = static_cast<std::uint8_t>(i % 4);
    leaves.push_back(l);
  }
  return leaves;
}

// FSA: n leaves collapse into one binary tree of 2n - 1 elements; cuts by count give that many
// leaves; a collapsed leaf keeps its vertices from its children and roughly the pair's area.
TEST(Foliage, LeafCollapseBuildsBinaryForest) {
  const auto leaves = leaf_row(40);
  const LeafForest lf = build_leaf_forest(leaves);
  EXPECT_EQ(lf.forest.size(), 79u);
  EXPECT_EQ(lf.forest.roots(), 1u);
  for (std::size_t k : {40u, 20u, 7u, 1u}) EXPECT_EQ(lf.forest.cut_by_count(k).size(), k);
  EXPECT_EQ(lf.forest.cut_by_error(0).size(), 40u);
  // Errors are monotone towards the roots; cuts by error shrink as the error grows.
  for (std::size_t i = 0; i < lf.forest.size(); ++i)
    if (lf.forest.parent[i] >= 0) {
      EXPECT_LE(lf.forest.error[i], lf.forest.error[static_cast<std::size_t>(lf.forest.parent[i])]);
    }
  std::size_t prev = SIZE_MAX;
  for (double e : {0.0, 0.05, 0.2, 1.0, 10.0}) {
    const std::size_t n = lf.forest.cut_by_error(e).size();
    EXPECT_LE(n, prev);
    prev = n;
  }
  // The first collapse: two 18 cm^2 leaves -> a quad of two vertices each, area near 36 cm^2.
  const std::size_t first = 40;
  const LeafQuad& z = lf.quads[first];
  const LeafQuad& a = lf.quads[static_cast<std::size_t>(lf.forest.left[first])];
  const LeafQuad& b = lf.quads[static_cast<std::size_t>(lf.forest.right[first])];
  int from_a = 0, from_b = 0;
  for (const Vec3& v : z.v) {
    for (const Vec3& w : a.v) from_a += v == w ? 1 : 0;
    for (const Vec3& w : b.v) from_b += v == w ? 1 : 0;
  }
  EXPECT_EQ(from_a, 2);
  EXPECT_EQ(from_b, 2);
  EXPECT_NEAR(z.area, a.area + b.area, 0.5 * (a.area + b.area));
}

// A collapsed leaf shows one whole atlas leaf: the larger leaf's variant cell, corner for corner
// (petiole edge at low v from the first leaf, tip edge at high v from the second).
TEST(Foliage, CollapsedLeafShowsAWholeAtlasLeaf) {
  tree::Leaf la, lb;
  la.position = {0, 0, 0};
  lb.position = {0.02f, 0.01f, 0};
  la.direction = lb.direction = {0, 1, 0};
  la.normal = lb.normal = {0, 0, 1};
  la.length = 0.06f;
  la.width = 0.03f;
  lb.length = 0.04f;
  lb.width = 0.02f;
  la.variant = 3;  // bottom-right cell: u, v in [0.5, 1]
  lb.variant = 0;
  for (bool swapped : {false, true}) {
    const LeafQuad qa = leaf_quad(la), qb = leaf_quad(lb);
    const LeafQuad z = swapped ? collapse_leaves(qb, qa) : collapse_leaves(qa, qb);
    std::set<std::pair<float, float>> corners;
    for (const auto& uv : z.uv) corners.insert({uv[0], uv[1]});
    const std::set<std::pair<float, float>> cell = {{0.5f, 0.5f}, {1.f, 0.5f}, {1.f, 1.f}, {0.5f, 1.f}};
    EXPECT_EQ(corners, cell) << swapped;
  }
}

// E5 needle merging: pairs of parallel neighbours go first; cuts by error fall with E5 and the
// error bounds every original needle's endpoint displacement.
TEST(Needles, PairwiseMergingCutByError) {
  std::vector<tree::Needle> ns;
  for (int i = 0; i < 30; ++i) {
    tree::Needle n;
    n.base = {static_cast<float>(i) * 0.01f, 0, 0};
    n.tip = {static_cast<float>(i) * 0.01f, 0.05f, 0.01f * static_cast<float>(i % 2)};
    n.radius = 0.0005f;
    ns.push_back(n);
  }
  const NeedleForest nf = build_needle_forest(ns);
  EXPECT_EQ(nf.forest.size(), 59u);
  std::size_t prev = SIZE_MAX;
  for (double e : {0.0, 0.01, 0.03, 0.1, 1.0}) {
    const auto cut = nf.forest.cut_by_error(e);
    EXPECT_LE(cut.size(), prev);
    prev = cut.size();
    // Every original is represented exactly once.
    std::size_t ranks = 0;
    for (auto id : cut) ranks += nf.needles[id].rank;
    EXPECT_EQ(ranks, 30u);
  }
  BranchGeometry g;
  const auto all = nf.forest.cut_by_error(0);
  needle_geometry(nf, all, 0.004, 12, g);  // rho = 8: lines
  EXPECT_EQ(g.lines, 90u);
}

// The chain runs its precomputations and levels as parallel tasks: the result must equal the
// sequential computation bit for bit (counts, alpha and every vertex of every level).
TEST(Chain, ParallelEqualsSequential) {
  const tree::Tree& t =
      test::species_tree(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species/oak.yaml", "young");
  ChainOptions o;
  const std::vector<Level> parallel = build_chain(t, o);
  const Precomputed pre = precompute(t, o);
  const std::vector<LevelSpec> specs = plan_levels(o);
  ASSERT_EQ(parallel.size(), specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const Level seq = build_level(t, pre, specs[i], o);
    EXPECT_EQ(parallel[i].counts.total(), seq.counts.total()) << i;
    EXPECT_EQ(parallel[i].line_alpha, seq.line_alpha) << i;
    EXPECT_EQ(parallel[i].branches.tri_positions, seq.branches.tri_positions) << i;
    EXPECT_EQ(parallel[i].branches.line_positions, seq.branches.line_positions) << i;
    EXPECT_EQ(parallel[i].leaves.positions, seq.leaves.positions) << i;
    EXPECT_EQ(parallel[i].kept_nodes, seq.kept_nodes) << i;
  }
}

}  // namespace
}  // namespace sylva::lod
