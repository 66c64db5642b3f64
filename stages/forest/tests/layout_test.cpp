// Celba §4.5.3 / Algorithm 8 and the §4.5.4 improvements, checked on small forests.
#include "stages/forest/layout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "stages/forest/hierarchy.h"
#include "stages/forest/positions_csv.h"

namespace sylva::forest {
namespace {

SpeciesRule rule(const std::string& name, double density, double half_width, double height) {
  SpeciesRule s;
  s.name = name;
  s.density_per_ha = density;
  s.bounds = {{-half_width, 0, -half_width}, {half_width, height, half_width}};
  return s;
}

double overlap(const Box3& a, const Box3& b) {
  double v = 1;
  for (int k = 0; k < 3; ++k) v *= std::max(0.0, std::min(a.max[k], b.max[k]) - std::max(a.min[k], b.min[k]));
  return v;
}
double volume(const Box3& b) { return (b.max[0] - b.min[0]) * (b.max[1] - b.min[1]) * (b.max[2] - b.min[2]); }

TEST(Layout, CelbaCountsAndTheAnyOneOverlapRule) {
  LayoutParams p;
  p.width_m = 100;
  p.depth_m = 80;
  p.allow_intersection = 0.3;
  p.retries = 20;
  p.species = {rule("a", 200, 3, 10), rule("b", 100, 2, 6)};
  p.species[0].scale_y = {0.8, 1.2};
  Rng rng(1, "layout");
  const LayoutResult r = lay_out(p, rng);
  ASSERT_EQ(r.stats.size(), 2u);
  EXPECT_EQ(r.stats[0].requested, 160u);  // 200 per ha x 0.8 ha
  EXPECT_EQ(r.stats[1].requested, 80u);
  EXPECT_EQ(r.stats[0].placed + r.stats[0].dropped, 160u);
  EXPECT_EQ(r.stats[1].placed + r.stats[1].dropped, 80u);
  EXPECT_EQ(r.trees.size(), r.stats[0].placed + r.stats[1].placed);
  // Types in order: every tree of species a comes before every tree of b.
  bool seen_b = false;
  for (const auto& t : r.trees) {
    if (t.species == 1) seen_b = true;
    EXPECT_FALSE(seen_b && t.species == 0);
  }
  // Each tree overlaps each EARLIER tree by at most 0.3 of its own volume; the sum may be more.
  bool summed_more = false;
  for (std::size_t i = 0; i < r.trees.size(); ++i) {
    double sum = 0;
    for (std::size_t j = 0; j < i; ++j) {
      const double v = overlap(r.trees[i].box, r.trees[j].box);
      EXPECT_LE(v, 0.3 * volume(r.trees[i].box) + 1e-9) << i << " vs " << j;
      sum += v;
    }
    summed_more = summed_more || sum > 0.3 * volume(r.trees[i].box);
    EXPECT_LE(std::abs(r.trees[i].position[0]), 50.0);
    EXPECT_LE(std::abs(r.trees[i].position[2]), 40.0);
    EXPECT_GE(r.trees[i].scale[1], r.trees[i].species == 0 ? 0.8 : 1.0);
  }
  EXPECT_TRUE(summed_more) << "Algorithm 8 tests boxes one at a time, not their summed overlap";
}

TEST(Layout, DenseForestDropsTreesAndReportsThem) {
  LayoutParams p;
  p.width_m = p.depth_m = 20;
  p.allow_intersection = 0;
  p.retries = 5;
  p.species = {rule("a", 1000, 2, 5)};  // 40 trees of 4 x 4 m on 400 m^2: cannot all fit
  Rng rng(3, "layout");
  const LayoutResult r = lay_out(p, rng);
  EXPECT_EQ(r.stats[0].requested, 40u);
  EXPECT_GT(r.stats[0].dropped, 0u);
  EXPECT_EQ(r.stats[0].placed, r.trees.size());
  for (std::size_t i = 0; i < r.trees.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) EXPECT_EQ(overlap(r.trees[i].box, r.trees[j].box), 0.0);
}

TEST(Layout, SameSeedSameForestOtherSeedOther) {
  LayoutParams p;
  p.species = {rule("a", 50, 2, 8)};
  Rng r1(9, "layout"), r2(9, "layout"), r3(10, "layout");
  const auto a = lay_out(p, r1), b = lay_out(p, r2), c = lay_out(p, r3);
  ASSERT_EQ(a.trees.size(), b.trees.size());
  for (std::size_t i = 0; i < a.trees.size(); ++i) {
    EXPECT_EQ(a.trees[i].position, b.trees[i].position);
    EXPECT_EQ(a.trees[i].yaw_rad, b.trees[i].yaw_rad);
  }
  EXPECT_NE(a.trees[0].position, c.trees[0].position);
}

TEST(Layout, YawedBoxIsTheBoxOfTheRotatedFootprint) {
  SpeciesRule s = rule("a", 1, 1, 2);
  s.bounds = {{-2, 0, -1}, {2, 2, 1}};
  const Box3 b = tree_box(s, {10, 1, 0}, std::acos(-1.0) / 2, {1, 1, 1});
  EXPECT_NEAR(b.min[0], 9, 1e-12);
  EXPECT_NEAR(b.max[0], 11, 1e-12);
  EXPECT_NEAR(b.min[2], -2, 1e-12);
  EXPECT_NEAR(b.max[1], 3, 1e-12);
}

TEST(Layout, ExclusionsLowerTheCountAndStayEmpty) {
  LayoutParams p;
  p.species = {rule("a", 100, 1, 4)};
  p.exclusions = {{{-50, -50}, {0, -50}, {0, 50}, {-50, 50}}};  // the west half: a glade
  Rng rng(2, "layout");
  const LayoutResult r = lay_out(p, rng);
  EXPECT_EQ(r.stats[0].requested, 50u);
  for (const auto& t : r.trees) EXPECT_GE(t.position[0], 0.0);
}

TEST(Layout, RowsPlaceTreesAtTheirSpacingFirst) {
  LayoutParams p;
  p.species = {rule("a", 10, 1, 4), rule("b", 0, 1, 4)};
  p.rows = {{1, {{-40, 0}, {0, 0}, {0, 20}}, 10, 0}};
  p.explicit_trees = {{0, {5, 5}, 30, 1.5, 2}};
  Rng rng(2, "layout");
  const LayoutResult r = lay_out(p, rng);
  ASSERT_GE(r.trees.size(), 8u);
  EXPECT_EQ(r.trees[0].position, (Vec3d{5, 0, 5}));  // explicit first
  EXPECT_NEAR(r.trees[0].yaw_rad, std::acos(-1.0) / 6, 1e-12);
  EXPECT_EQ(r.trees[0].scale, (Vec3d{1.5, 1.5, 1.5}));
  const double xs[] = {-40, -30, -20, -10, 0, 0, 0};
  const double zs[] = {0, 0, 0, 0, 0, 10, 20};
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(r.trees[std::size_t(i) + 1].species, 1u);
    EXPECT_NEAR(r.trees[std::size_t(i) + 1].position[0], xs[i], 1e-9);
    EXPECT_NEAR(r.trees[std::size_t(i) + 1].position[2], zs[i], 1e-9);
  }
  EXPECT_EQ(r.stats[1].requested, 7u);
  EXPECT_EQ(r.stats[1].placed, 7u);
}

TEST(Layout, TerrainSetsTreesOnTheGroundWithinTheirLimits) {
  LayoutParams p;
  p.species = {rule("a", 200, 0.5, 4)};
  p.species[0].max_slope_deg = 20;
  p.species[0].max_altitude_m = 30;
  // A ramp rising 0 -> 50 m along +x over the west half, flat at 50 m in the east half.
  p.terrain.height_min = 0;
  p.terrain.height_max = 50;
  p.terrain.field = {3, 2, {0.f, 1.f, 1.f, 0.f, 1.f, 1.f}, -50, -50, 50, 50};
  Rng rng(5, "layout");
  const LayoutResult r = lay_out(p, rng);
  // The ramp's slope is atan(50 / 50) = 45 deg: too steep; the plateau is flat but at 50 m: too high.
  EXPECT_LT(r.stats[0].requested, 5u);
  EXPECT_LE(r.trees.size(), r.stats[0].requested);
  for (const auto& t : r.trees) {
    EXPECT_NEAR(t.position[1], p.terrain.height(t.position[0], t.position[2]), 1e-12);
    EXPECT_LE(p.terrain.slope_deg(t.position[0], t.position[2]), 20.0);
  }
  // Gentler ramp: everything below 30 m grows.
  p.terrain.height_max = 10;
  p.species[0].max_altitude_m = 8;
  Rng rng2(5, "layout");
  const LayoutResult r2 = lay_out(p, rng2);
  EXPECT_GT(r2.trees.size(), 60u);  // the ramp below 8 m: 40 % of the area
  for (const auto& t : r2.trees) {
    EXPECT_LE(t.position[1], 8.0 + 1e-9);
    EXPECT_NEAR(t.position[1], p.terrain.height(t.position[0], t.position[2]), 1e-12);
  }
}

TEST(Layout, DensityMapShiftsTreesToWhereItIsHigh) {
  LayoutParams p;
  p.species = {rule("a", 100, 0.5, 4)};
  p.density = {2, 2, {0.f, 1.f, 0.f, 1.f}, -50, -50, 50, 50};  // 0 on the west edge, 1 on the east
  Rng rng(4, "layout");
  const LayoutResult r = lay_out(p, rng);
  EXPECT_EQ(r.stats[0].requested, 50u);  // mean of the map is 1/2
  int east = 0;
  for (const auto& t : r.trees) east += t.position[0] > 0 ? 1 : 0;
  EXPECT_GT(east, int(r.trees.size()) * 2 / 3);
}

TEST(Layout, PoissonKeepsEverySpacingAndTheMix) {
  LayoutParams p;
  p.method = Method::kPoisson;
  p.retries = 30;
  p.species = {rule("a", 40, 1, 4), rule("b", 20, 1, 4)};
  p.species[0].min_spacing_m = 6;
  p.species[1].min_spacing_m = 9;
  Rng rng(6, "layout");
  const LayoutResult r = lay_out(p, rng);
  EXPECT_EQ(r.stats[0].requested, 40u);
  EXPECT_EQ(r.stats[1].requested, 20u);
  EXPECT_EQ(r.stats[0].placed, 40u);
  EXPECT_EQ(r.stats[1].placed, 20u);
  for (std::size_t i = 0; i < r.trees.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      const double need =
          std::max(p.species[r.trees[i].species].min_spacing_m, p.species[r.trees[j].species].min_spacing_m);
      EXPECT_GE(std::hypot(r.trees[i].position[0] - r.trees[j].position[0],
                           r.trees[i].position[2] - r.trees[j].position[2]),
                need - 1e-9);
    }
}

// Densities or rows that would request more trees than a forest may hold are refused before
// anything is allocated (before: std::bad_alloc, or minutes in the row loop).
TEST(Layout, RefusesMoreThanTwentyMillionRequestedTrees) {
  const std::string why =
      " trees (densities over the area, rows, positions), more than the 20,000,000 a forest may hold: lower "
      "density_per_ha or size_m, or raise the rows' spacing_m";
  auto error = [](const LayoutParams& p) {
    Rng rng(1, "layout");
    try {
      lay_out(p, rng);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  LayoutParams dense;
  dense.width_m = dense.depth_m = 1e6;
  dense.species = {rule("a", 1e6, 1, 4)};
  EXPECT_EQ(requested_trees(dense), 1e14);
  EXPECT_EQ(error(dense), "the forest would request 1e+14" + why);
  LayoutParams row;
  row.width_m = row.depth_m = 1e6;
  row.species = {rule("a", 0, 1, 4)};
  row.rows = {{0, {{-4e5, 0}, {4e5, 0}}, 0.03125, 0}};  // a spacing exact in binary
  EXPECT_EQ(requested_trees(row), 2.56e7 + 1);
  EXPECT_EQ(error(row), "the forest would request 2.56e+07" + why);
  LayoutParams fits = dense;
  fits.species[0].density_per_ha = 2e7 / 1e8;  // 2e7 trees over 1e8 ha
  EXPECT_EQ(requested_trees(fits), 2e7);
}

TEST(Layout, PoissonReportsWhatDoesNotFit) {
  LayoutParams p;
  p.method = Method::kPoisson;
  p.width_m = p.depth_m = 30;
  p.species = {rule("a", 1000, 1, 4)};  // 90 trees at >= 10 m spacing on 900 m^2: about 9 fit
  p.species[0].min_spacing_m = 10;
  Rng rng(6, "layout");
  const LayoutResult r = lay_out(p, rng);
  EXPECT_EQ(r.stats[0].requested, 90u);
  EXPECT_LT(r.stats[0].placed, 20u);
  EXPECT_EQ(r.stats[0].placed + r.stats[0].dropped, 90u);
}

TEST(Layout, PositionsCsv) {
  const auto t = parse_positions_csv("# park\nx, z, species, yaw_deg\n1, 2, oak, -90\n3.5,4,birch,0\n",
                                     {"oak", "birch"}, "p.csv");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].species, 0u);
  EXPECT_EQ(t[0].position, (Point2{1, 2}));
  EXPECT_EQ(t[0].yaw_deg, 270);
  EXPECT_EQ(t[0].line, 3);
  EXPECT_EQ(t[1].species, 1u);
  EXPECT_LT(t[1].scale, 0);
  auto msg = [](const std::string& text) {
    try {
      parse_positions_csv(text, {"oak"}, "p.csv");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(msg("species,x,z\noak,1\n"), "p.csv:2: expected 3 values, got 2");
  EXPECT_EQ(msg("species,x,z\nelm,1,2\n"), "p.csv:2: unknown species 'elm'");
  EXPECT_EQ(msg("species,x,z\noak,1,two\n"), "p.csv:2: z 'two' is not a number");
  EXPECT_EQ(msg("species,x,y\n"), "p.csv:1: unknown column 'y' (expected species, x, z, yaw_deg, scale)");
  EXPECT_EQ(
      msg(""),
      "p.csv: no header line (species,x,z[,yaw_deg][,scale]): the file is empty or holds only comments");
  // Scales within the species parameters' range; hexadecimal and NUL-split numbers refused; a
  // long or binary cell quoted short and escaped; a byte order mark ignored.
  EXPECT_EQ(msg("species,x,z,scale\noak,1,2,1e300\n"), "p.csv:2: scale must lie in 0.001..1000");
  EXPECT_EQ(msg("species,x,z,scale\noak,1,2,0.0001\n"), "p.csv:2: scale must lie in 0.001..1000");
  EXPECT_EQ(msg("species,x,z\noak,0x10,2\n"), "p.csv:2: x '0x10' is not a number");
  EXPECT_EQ(msg(std::string("species,x,z\noak,1\0junk,2\n", 25)), "p.csv:2: x '1\\x00junk' is not a number");
  EXPECT_EQ(msg("species,x,z\noak,1," + std::string(100, 'q') + "\n"),
            "p.csv:2: z '" + std::string(40, 'q') + "...' is not a number");
  EXPECT_EQ(msg("species,x,z\n\xC3\xA9lm,1,2\n"), "p.csv:2: unknown species '\\xC3\\xA9lm'");
  EXPECT_EQ(msg("\xEF\xBB\xBFspecies,x,z\noak,1,2\n"), "");
}

// Every node has 1..limit children, bounds its children, each box is under exactly one leaf,
// every node but the root (node 0) has one parent.
void expect_hierarchy(const std::vector<Box3>& boxes, int limit) {
  const auto nodes = build_hierarchy(boxes, limit);
  ASSERT_FALSE(nodes.empty());
  std::vector<int> seen(boxes.size(), 0);
  std::vector<int> parents(nodes.size(), 0);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    EXPECT_LE(nodes[n].children.size(), std::size_t(limit));
    EXPECT_GE(nodes[n].children.size(), 1u);
    for (auto c : nodes[n].children) {
      const Box3& cb = nodes[n].leaf ? boxes[c] : nodes[c].bounds;
      for (int k = 0; k < 3; ++k) {
        EXPECT_LE(nodes[n].bounds.min[k], cb.min[k]);
        EXPECT_GE(nodes[n].bounds.max[k], cb.max[k]);
      }
      if (nodes[n].leaf)
        ++seen[c];
      else
        ++parents[c];
    }
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_EQ(parents[0], 0);  // the root
  for (std::size_t n = 1; n < nodes.size(); ++n) EXPECT_EQ(parents[n], 1);
}

TEST(Hierarchy, NodesOfAtMostNodesPerNodeUpToOneRoot) {
  LayoutParams p;
  p.species = {rule("a", 300, 1, 4)};
  Rng rng(8, "layout");
  const LayoutResult r = lay_out(p, rng);
  std::vector<Box3> boxes;
  for (const auto& t : r.trees) boxes.push_back(t.box);
  expect_hierarchy(boxes, 16);
}

// With 2 or 3 children per node the quadtree alone can leave a level of nodes unshrunk (each in
// a quadrant of its own): the hierarchy still ends at one root. Before the fix this looped,
// allocating until it ran out of memory.
TEST(Hierarchy, TwoOrThreeChildrenPerNodeReachTheRoot) {
  for (int limit : {2, 3}) {
    for (std::size_t n : {3u, 4u, 5u, 17u, 300u}) {
      SCOPED_TRACE("limit " + std::to_string(limit) + ", " + std::to_string(n) + " boxes");
      std::vector<Box3> boxes;
      for (std::size_t i = 0; i < n; ++i) {
        const double x = double(i % 7) * 13.0 - double(i) * 0.5, z = double(i / 7) * 11.0 + double(i % 3);
        boxes.push_back({{x, 0, z}, {x + 1, 5, z + 1}});
      }
      expect_hierarchy(boxes, limit);
    }
  }
}

TEST(Hierarchy, TilesHoldTheirTrees) {
  std::vector<Instance> in(3);
  in[0].position = {-49, 0, -49};
  in[1].position = {10, 0, -49};
  in[2].position = {-1, 0, 30};
  std::vector<Box3> boxes(3);
  for (int i = 0; i < 3; ++i)
    boxes[std::size_t(i)] = {in[std::size_t(i)].position, in[std::size_t(i)].position};
  const auto tiles = build_tiles(in, boxes, {-50, -50}, 50);
  ASSERT_EQ(tiles.size(), 3u);
  EXPECT_EQ(tiles[0].ix, 0);
  EXPECT_EQ(tiles[0].iz, 0);
  EXPECT_EQ(tiles[1].ix, 1);
  EXPECT_EQ(tiles[1].iz, 0);
  EXPECT_EQ(tiles[2].ix, 0);
  EXPECT_EQ(tiles[2].iz, 1);
  EXPECT_EQ(in[2].tile, 2u);
}

}  // namespace
}  // namespace sylva::forest
