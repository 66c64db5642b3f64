// Recipe loading: one test per error class (exact message and position), then the features
// (matrix, includes, defaults, globs) on small hand-written recipes.
#include <gtest/gtest.h>

#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

class RecipeTest : public ::testing::Test {
 protected:
  RecipeTest() { test::register_test_stages(reg_, nullptr); }

  // Writes `yaml` as r.yaml (plus extra files) and loads it. Paths in messages are made
  // relative to the temp dir so expectations read like what a user sees.
  std::optional<Recipe> load(const std::string& yaml) {
    test::write_file(dir_ / "r.yaml", yaml);
    diags_ = Diagnostics();
    return load_recipe(dir_ / "r.yaml", reg_, fs_, diags_);
  }
  std::string errors() {
    std::string s = diags_.str();
    const std::string prefix = dir_.path().string() + "/";
    for (std::size_t p; (p = s.find(prefix)) != std::string::npos;) s.erase(p, prefix.size());
    return s;
  }
  void file(const std::string& name, const std::string& text) { test::write_file(dir_ / name, text); }

  test::TempDir dir_;
  StageRegistry reg_;
  RealFileSystem fs_;
  Diagnostics diags_;
};

// --- error classes ------------------------------------------------------------------------

TEST_F(RecipeTest, UnknownStageSuggestsClosest) {
  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  a:\n    stage: txet\n"));
  EXPECT_EQ(errors(), "r.yaml:5:12: error: unknown stage 'txet'; did you mean 'text'?\n");
}

TEST_F(RecipeTest, UnknownParameterSuggestsClosest) {
  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { txet: hi }\n"));
  EXPECT_EQ(errors(),
            "r.yaml:6:13: error: unknown parameter 'txet' for stage 'text'; did you mean 'text'?\n");
}

TEST_F(RecipeTest, WrongType) {
  EXPECT_FALSE(load(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with:\n      count: many\n      fail: 3\n"));
  EXPECT_EQ(errors(),
            "r.yaml:7:14: error: wrong type: parameter 'count' expects int, got 'many'\n"
            "r.yaml:8:13: error: wrong type: parameter 'fail' expects bool, got '3'\n");
}

TEST_F(RecipeTest, ValueOutOfRange) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { scale: 10.5, count: -1 }\n"));
  EXPECT_EQ(errors(),
            "r.yaml:6:20: error: value out of range: parameter 'scale' must be in [0, 10], got 10.5\n"
            "r.yaml:6:33: error: value out of range: parameter 'count' must be in [0, 1000], got -1\n");
}

TEST_F(RecipeTest, EnumChoiceAndNestedObjectField) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with:\n      mode: uper\n"
           "      camera: { fov_y: 40 }\n"));
  EXPECT_EQ(
      errors(),
      "r.yaml:7:13: error: parameter 'mode' must be one of plain, upper, got 'uper'; did you mean 'upper'?\n"
      "r.yaml:8:17: error: unknown field 'fov_y' in parameter 'camera'; did you mean 'fov_y_deg'?\n");
}

TEST_F(RecipeTest, ObjectListItemsAreCheckedOneByOne) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with:\n"
           "      items: [{ name: x, weight: 11 }, { wieght: 2 }]\n"));
  EXPECT_EQ(errors(),
            "r.yaml:7:34: error: value out of range: parameter 'items'[0].weight must be in [0, 10], got 11\n"
            "r.yaml:7:42: error: unknown field 'wieght' in parameter 'items'[1]; did you mean 'weight'?\n"
            "r.yaml:7:40: error: missing required field 'name' in parameter 'items'[1]\n");
  // A required field that is present but wrong is reported once, as wrong, not also as missing.
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with:\n"
           "      items: [{ name: [x] }]\n"));
  EXPECT_EQ(errors(),
            "r.yaml:7:23: error: wrong type: parameter 'items'[0].name expects string, got a list\n");
  auto r = load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { items: [{ name: x }] }\n");
  ASSERT_TRUE(r);
  const Value& items = r->nodes.at(0).params.at("items");
  ASSERT_EQ(items.as_list().size(), 1u);
  EXPECT_EQ(items.canonical(), "[{\"name\":\"x\",\"weight\":1.0}]");
}

// A stage's own checks (StageInfo::check) are recipe errors at the value they are about: inside
// a list of objects, or in the recipe's defaults; none when the schema already failed.
TEST_F(RecipeTest, StageChecksPointAtTheValue) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with:\n"
           "      items: [{ name: x }, { name: y }, { name: x }]\n"));
  EXPECT_EQ(errors(), "r.yaml:7:49: error: parameter 'items'[2].name: 'x' is the name of items[0] too\n");
  EXPECT_FALSE(load("version: 1\nname: r\ndefaults: { text: forbidden }\nnodes:\n  a:\n    stage: text\n"));
  EXPECT_EQ(errors(), "r.yaml:3:19: error: parameter 'text': 'forbidden' is not allowed\n");
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: forbidden, count: x }\n"));
  EXPECT_EQ(errors(), "r.yaml:6:37: error: wrong type: parameter 'count' expects int, got 'x'\n");
}

// Checks that need the resolved inputs (StageInfo::check_inputs) run after `needs`, at the value.
TEST_F(RecipeTest, StageInputChecksPointAtTheValue) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n  b:\n    stage: text\n"
           "  c:\n    stage: concat\n    needs: [a, b]\n    with: { suffix: '#3' }\n"));
  EXPECT_EQ(errors(), "r.yaml:11:21: error: parameter 'suffix': says 3 inputs, the node has 2\n");
  EXPECT_TRUE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n  b:\n    stage: text\n"
           "  c:\n    stage: concat\n    needs: [a, b]\n    with: { suffix: '#2' }\n"));
}

TEST_F(RecipeTest, MissingInputNode) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  base:\n    stage: text\n"
           "  b:\n    stage: concat\n    needs: [bsae, lod_*]\n"));
  EXPECT_EQ(errors(),
            "r.yaml:8:13: error: missing input: no node named 'bsae'; did you mean 'base'?\n"
            "r.yaml:8:19: error: missing input: no node matches 'lod_*'\n"
            "r.yaml:8:12: error: node 'b' (stage 'concat') needs at least 1 input, got 0\n");
}

TEST_F(RecipeTest, MissingInputFile) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: readfile\n    with: { file: nope.txt }\n"));
  EXPECT_EQ(
      errors(),
      "r.yaml:6:19: error: missing input: parameter 'file' names file 'nope.txt', which does not exist\n");
}

TEST_F(RecipeTest, MissingRequiredParameter) {
  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  a:\n    stage: readfile\n"));
  EXPECT_EQ(errors(),
            "r.yaml:4:3: error: node 'a' (stage 'readfile') is missing required parameter 'file'\n");
}

TEST_F(RecipeTest, DuplicateNode) {
  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n  a:\n    stage: text\n"));
  EXPECT_EQ(errors(), "r.yaml:6:3: error: duplicate node 'a' (first defined at r.yaml:4:3)\n");
}

TEST_F(RecipeTest, CycleIsPrinted) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n"
           "  a:\n    stage: concat\n    needs: c\n"
           "  b:\n    stage: concat\n    needs: a\n"
           "  c:\n    stage: concat\n    needs: b\n"));
  EXPECT_EQ(errors(), "r.yaml:4:3: error: dependency cycle: a -> c -> b -> a\n");
}

TEST_F(RecipeTest, UnreadableFile) {
  Diagnostics d;
  EXPECT_FALSE(load_recipe(dir_ / "missing.yaml", reg_, fs_, d));
  EXPECT_EQ(d.str(),
            "error: cannot read '" + (dir_ / "missing.yaml").string() + "': No such file or directory\n");
}

TEST_F(RecipeTest, MalformedYaml) {
  EXPECT_FALSE(load("version: 1\nname: r\nnodes: [a, b\n"));
  EXPECT_EQ(errors(), "r.yaml:4:1: error: malformed YAML: end of sequence flow not found\n");
}

TEST_F(RecipeTest, NodeNamesCannotEscapeOut) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  ../evil:\n    stage: text\n  a/b:\n    stage: text\n  ..:\n    "
           "stage: text\n"));
  EXPECT_EQ(errors(),
            "r.yaml:4:3: error: invalid node name '../evil': use letters, digits, '_', '-' and '.' (no path "
            "separators)\n"
            "r.yaml:6:3: error: invalid node name 'a/b': use letters, digits, '_', '-' and '.' (no path "
            "separators)\n"
            "r.yaml:8:3: error: invalid node name '..': use letters, digits, '_', '-' and '.' (no path "
            "separators)\n");
}

TEST_F(RecipeTest, RecipeNameIsCheckedToo) {
  EXPECT_FALSE(load("version: 1\nname: ../x\nnodes: {}\n"));
  EXPECT_EQ(errors(),
            "r.yaml:2:7: error: invalid recipe name '../x': use letters, digits, '_', '-' and '.'\n");
}

TEST_F(RecipeTest, UnknownKeysEverywhere) {
  EXPECT_FALSE(load("version: 1\nname: r\nnode: {}\nnodes:\n  a:\n    stage: text\n    neds: [x]\n"));
  EXPECT_EQ(errors(),
            "r.yaml:3:1: error: unknown key 'node'; did you mean 'nodes'?\n"
            "r.yaml:7:5: error: unknown key 'neds' in node 'a'; did you mean 'needs'?\n");
}

TEST_F(RecipeTest, VersionAndNameRequired) {
  EXPECT_FALSE(load("version: 2\nnodes: {}\n"));
  EXPECT_EQ(errors(),
            "r.yaml:1:10: error: unsupported recipe version '2' (this sylva reads version 1)\n"
            "r.yaml:1:1: error: missing required key 'name'\n");
}

TEST_F(RecipeTest, WrongInputType) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n  m:\n    stage: mesh_only\n    needs: a\n"));
  EXPECT_EQ(errors(),
            "r.yaml:8:12: error: node 'm' cannot take 'a' as input: stage 'mesh_only' accepts mesh, but 'a' "
            "makes a text\n");
}

TEST_F(RecipeTest, AllErrorsReportedTogetherWithCaret) {
  EXPECT_FALSE(load(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { count: x }\n  b:\n    stage: nope\n"));
  ASSERT_EQ(diags_.size(), 2u);
  EXPECT_EQ(diags_.all()[0].pretty().substr(diags_.all()[0].pretty().find('\n')),
            "\n      with: { count: x }\n                     ^");
}

// --- features --------------------------------------------------------------------------

TEST_F(RecipeTest, MatrixExpandsNamesInOrderAndSubstitutes) {
  auto r = load(
      "version: 1\nname: r\nmatrix:\n  species: [oak, birch]\n  age: [young, adult]\n"
      "nodes:\n  t_${species}_${age}:\n    stage: text\n    with: { text: '${species}/${age} costs $${x}' }\n"
      "  all:\n    stage: concat\n    needs: 't_*'\n");
  ASSERT_TRUE(r) << errors();
  ASSERT_EQ(r->nodes.size(), 5u);
  EXPECT_EQ(r->nodes[0].name, "t_oak_young");
  EXPECT_EQ(r->nodes[1].name, "t_oak_adult");
  EXPECT_EQ(r->nodes[2].name, "t_birch_young");
  EXPECT_EQ(r->nodes[3].name, "t_birch_adult");
  EXPECT_EQ(r->nodes[1].params.at("text").as_string(), "oak/adult costs ${x}");
  EXPECT_EQ(r->nodes[4].needs,
            (std::vector<std::string>{"t_birch_adult", "t_birch_young", "t_oak_adult", "t_oak_young"}));
}

TEST_F(RecipeTest, MatrixVariableErrors) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nmatrix: { a: [x, y] }\nnodes:\n  n_${b}:\n    stage: text\n"
           "  m:\n    stage: text\n    with: { text: '${a}' }\n"));
  EXPECT_EQ(errors(),
            "r.yaml:5:3: error: unknown variable '${b}'; did you mean 'a'?\n"
            "r.yaml:9:19: error: variable '${a}' is used in node 'm' but not in its name, so its expansions "
            "would share one name\n");
}

// Found by fuzz_recipe: a variable whose only value is refused used to expand its node over an
// empty list (an out-of-range read).
TEST_F(RecipeTest, MatrixVariableWithNoScalarValueIsAnErrorNotAnExpansion) {
  EXPECT_FALSE(load("version: 1\nname: r\nmatrix:\n  s: [oak: birch]\nnodes:\n  t_${s}:\n    stage: text\n"));
  EXPECT_EQ(errors(), "r.yaml:4:7: error: matrix values must be scalars\n");
}

TEST_F(RecipeTest, NodeLevelMatrixOverrides) {
  auto r = load(
      "version: 1\nname: r\nmatrix: { n: [1, 2, 3] }\nnodes:\n  t${n}:\n    stage: text\n    matrix: { n: "
      "[7] }\n");
  ASSERT_TRUE(r) << errors();
  ASSERT_EQ(r->nodes.size(), 1u);
  EXPECT_EQ(r->nodes[0].name, "t7");
}

TEST_F(RecipeTest, IncludesMergeFragmentsAndValues) {
  file("sub/common.yaml", "defaults: { count: 3 }\nnodes:\n  shared:\n    stage: text\n");
  file("cam.yaml", "fov_y_deg: 30\nheight_px: 720\n");
  auto r = load(
      "version: 1\nname: r\ninclude: [sub/common.yaml]\nnodes:\n  a:\n    stage: text\n    with: { camera: "
      "!include cam.yaml }\n");
  ASSERT_TRUE(r) << errors();
  ASSERT_EQ(r->nodes.size(), 2u);
  EXPECT_EQ(r->nodes[0].name, "shared");
  EXPECT_EQ(r->nodes[0].params.at("count").as_int(), 3);  // default from the fragment
  EXPECT_EQ(r->nodes[1].params.at("camera").canonical(), "{\"fov_y_deg\":30.0,\"height_px\":720}");
}

TEST_F(RecipeTest, IncludeErrorsPointIntoTheIncludedFile) {
  file("frag.yaml", "nodes:\n  x:\n    stage: text\n    with: { count: oops }\n");
  file("loop.yaml", "include: r.yaml\n");
  EXPECT_FALSE(load("version: 1\nname: r\ninclude: [frag.yaml, loop.yaml]\nnodes: {}\n"));
  EXPECT_EQ(errors(),
            "loop.yaml:1:10: error: include cycle: 'r.yaml' is already being read\n"
            "frag.yaml:4:20: error: wrong type: parameter 'count' expects int, got 'oops'\n");
}

TEST_F(RecipeTest, DefaultsApplyAndMisspelledDefaultsAreCaught) {
  auto r = load(
      "version: 1\nname: r\ndefaults: { scale: 2, camera: { height_px: 10 } }\nnodes:\n  a:\n    stage: "
      "text\n    with: { scale: 3 }\n  b:\n    stage: text\n");
  ASSERT_TRUE(r) << errors();
  EXPECT_EQ(r->nodes[0].params.at("scale").as_real(), 3.0);
  EXPECT_EQ(r->nodes[1].params.at("scale").as_real(), 2.0);
  EXPECT_EQ(r->nodes[1].params.at("camera").canonical(), "{\"fov_y_deg\":45.0,\"height_px\":10}");
  EXPECT_FALSE(load("version: 1\nname: r\ndefaults: { scael: 2 }\nnodes:\n  a:\n    stage: text\n"));
  EXPECT_EQ(errors(), "r.yaml:3:13: error: unknown parameter 'scael' in defaults; did you mean 'scale'?\n");
}

TEST_F(RecipeTest, PathParametersResolveRelativeToTheirFile) {
  file("sub/data.txt", "x");
  file("sub/frag.yaml", "nodes:\n  a:\n    stage: readfile\n    with: { file: data.txt }\n");
  auto r = load("version: 1\nname: r\ninclude: sub/frag.yaml\n");
  ASSERT_TRUE(r) << errors();
  EXPECT_EQ(r->nodes[0].files.at("file"), (dir_ / "sub/data.txt").lexically_normal());
}

TEST_F(RecipeTest, CanonicalParametersIgnoreSpelling) {
  auto a = load(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { scale: 1, weights: [1, 2.50] }\n");
  ASSERT_TRUE(a);
  auto b = load(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with:\n      weights: [1.0, 2.5]\n      "
      "scale: 1.0\n");
  ASSERT_TRUE(b);
  EXPECT_EQ(Value(a->nodes[0].params).canonical(), Value(b->nodes[0].params).canonical());
}

}  // namespace
}  // namespace sylva

namespace sylva {
namespace {
TEST_F(RecipeTest, UnquotedVariableInFlowMapGetsAHint) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nmatrix: { s: [a] }\nnodes:\n  t_${s}:\n    stage: text\n    with: { text: "
           "x/${s} }\n"));
  EXPECT_EQ(errors(),
            "r.yaml:7:22: error: malformed YAML: end of map flow not found (inside { } or [ ], quote values "
            "that contain ${...})\n");
}
}  // namespace
}  // namespace sylva
