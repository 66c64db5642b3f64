// Graph ordering and closure on small recipes.
#include "pipeline/graph.h"

#include <gtest/gtest.h>

#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

Recipe load(const std::string& yaml, test::TempDir& dir, StageRegistry& reg) {
  test::write_file(dir / "r.yaml", yaml);
  RealFileSystem fs;
  Diagnostics d;
  auto r = load_recipe(dir / "r.yaml", reg, fs, d);
  EXPECT_TRUE(r) << d.str();
  return r ? *r : Recipe{};
}

// A diamond declared bottom-up: order must still put inputs first, ties in declaration order.
TEST(GraphTest, TopologicalOrderRespectsInputsAndDeclarationOrder) {
  test::TempDir dir;
  StageRegistry reg;
  test::register_test_stages(reg, nullptr);
  Recipe r = load(
      "version: 1\nname: g\nnodes:\n"
      "  d:\n    stage: concat\n    needs: [b, c]\n"
      "  c:\n    stage: concat\n    needs: a\n"
      "  b:\n    stage: concat\n    needs: a\n"
      "  a:\n    stage: text\n"
      "  e:\n    stage: text\n",
      dir, reg);
  BuildGraph g(r);
  std::vector<std::string> order;
  for (auto i : g.topo_order()) order.push_back(r.nodes[i].name);
  EXPECT_EQ(order, (std::vector<std::string>{"a", "c", "b", "d", "e"}));
  // closure of c: c and a only
  auto mask = g.closure({r.index_of("c")});
  EXPECT_TRUE(mask[r.index_of("c")] && mask[r.index_of("a")]);
  EXPECT_FALSE(mask[r.index_of("b")] || mask[r.index_of("d")] || mask[r.index_of("e")]);
  EXPECT_EQ(g.dependents(r.index_of("a")).size(), 2u);
}

TEST(GraphTest, FindCycleReturnsTheLoop) {
  Recipe r;
  r.nodes.resize(3);
  r.nodes[0].name = "x";
  r.nodes[1].name = "y";
  r.nodes[2].name = "z";
  r.nodes[0].needs = {"z"};
  r.nodes[1].needs = {"x"};
  r.nodes[2].needs = {"y"};
  auto c = find_cycle(r);
  ASSERT_TRUE(c);
  EXPECT_EQ(*c, (std::vector<std::size_t>{0, 2, 1}));
  r.nodes[0].needs.clear();
  EXPECT_FALSE(find_cycle(r));
}

}  // namespace
}  // namespace sylva
