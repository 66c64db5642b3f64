// The parsed-YAML cache (pipeline/yaml_tree.h): a second load gives the same recipe and the
// same diagnostics (file:line:col, source line) without yaml-cpp; an edited file, an edited
// include, or a damaged entry are parsed again.
#include <gtest/gtest.h>

#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_filesystem.h"

namespace sylva {
namespace {

class ParseCacheTest : public ::testing::Test {
 protected:
  ParseCacheTest() { test::register_test_stages(reg_, nullptr); }

  std::optional<Recipe> load(bool cached = true) {
    diags_ = Diagnostics();
    return load_recipe("/p/r.yaml", reg_, fs_, diags_, cached ? "/o/.sylva-parse" : "");
  }
  static std::string describe(const Recipe& r) {
    std::string s = r.name + "\n";
    for (const auto& n : r.nodes) {
      s += n.name + "@" + std::to_string(n.loc.line) + ":" + std::to_string(n.loc.col) + " " +
           n.stage->info().name;
      for (const auto& [k, v] : n.params) s += " " + k + "=" + v.canonical();
      for (const auto& u : n.needs) s += " <" + u;
      s += "\n";
    }
    return s;
  }
  std::size_t entries() {
    std::size_t n = 0;
    for (const auto& [path, content] : fs_.files) n += path.rfind("/o/.sylva-parse/", 0) == 0;
    return n;
  }

  StageRegistry reg_;
  test::FakeFileSystem fs_;
  Diagnostics diags_;
};

TEST_F(ParseCacheTest, SecondLoadIsIdenticalAndEditsAreSeen) {
  fs_.put("/p/r.yaml",
          "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: A, count: 2 }\n"
          "  b: !include b.yaml\n");
  fs_.put("/p/b.yaml", "stage: concat\nneeds: [a]\nwith: { suffix: '!' }\n");
  auto plain = load(false);
  ASSERT_TRUE(plain) << diags_.str();
  auto first = load();
  ASSERT_TRUE(first) << diags_.str();
  EXPECT_EQ(entries(), 2u);  // one per file
  fs_.writes.clear();
  auto second = load();
  ASSERT_TRUE(second) << diags_.str();
  EXPECT_TRUE(fs_.writes.empty());  // served from the cache
  EXPECT_EQ(describe(*second), describe(*plain));
  EXPECT_EQ(describe(*first), describe(*plain));

  fs_.put("/p/b.yaml", "stage: concat\nneeds: [a]\nwith: { suffix: '?' }\n");  // the include changed
  auto third = load();
  ASSERT_TRUE(third);
  EXPECT_EQ(third->nodes.at(1).params.at("suffix").as_string(), "?");

  fs_.files["/o/.sylva-parse/" + sha256_hex("/p/r.yaml")].resize(40);  // damaged entry
  auto fourth = load();
  ASSERT_TRUE(fourth);
  EXPECT_EQ(describe(*fourth), describe(*third));
}

TEST_F(ParseCacheTest, ErrorsFromACachedTreeAreTheSame) {
  fs_.put("/p/r.yaml", "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { txet: A }\n");
  EXPECT_FALSE(load(false));
  const std::string plain = diags_.pretty();
  EXPECT_FALSE(load());
  EXPECT_FALSE(load());
  EXPECT_EQ(diags_.pretty(), plain);
  EXPECT_NE(plain.find("/p/r.yaml:6:"), std::string::npos) << plain;
}

}  // namespace
}  // namespace sylva
