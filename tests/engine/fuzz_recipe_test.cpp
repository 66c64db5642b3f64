// A deterministic mutation fuzzer for the recipe loader (the parser that reads outside data):
// thousands of byte-level mutations of a real recipe must each load or fail with diagnostics,
// never crash, hang or throw.
#include <gtest/gtest.h>

#include "pipeline/recipe_loader.h"
#include "pipeline/rng.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_filesystem.h"

namespace sylva {
namespace {

const char* kSeedRecipe =
    "version: 1\nname: fuzz\nmatrix:\n  s: [oak, birch]\n  a: [young, adult]\n"
    "defaults: { scale: 2, camera: { fov_y_deg: 40 } }\ninclude: [frag.yaml]\n"
    "nodes:\n  t_${s}_${a}:\n    stage: text\n    with: { text: '${s}', count: 3, weights: [1, 2.5], mode: "
    "upper }\n"
    "  all:\n    stage: concat\n    needs: ['t_*', f]\n    with: { suffix: '$${x}' }\n"
    "  r:\n    stage: readfile\n    with: { file: data.txt, }\n";

TEST(FuzzRecipeTest, MutatedRecipesNeverCrash) {
  StageRegistry reg;
  test::register_test_stages(reg, nullptr);
  Rng rng(2026, "fuzz-recipe");
  const std::string alphabet = "{}[]:,'\"$*?!&|>-\n #\t\\0123456789abcxyz_.";
  int loaded = 0, rejected = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    std::string text = kSeedRecipe;
    const int edits = 1 + static_cast<int>(rng.below(4));
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const std::size_t pos = rng.below(text.size());
      switch (rng.below(3)) {
        case 0:
          text[pos] = alphabet[rng.below(alphabet.size())];
          break;
        case 1:
          text.erase(pos, 1 + rng.below(8));
          break;
        default:
          text.insert(pos, 1, alphabet[rng.below(alphabet.size())]);
      }
    }
    test::FakeFileSystem fs;
    fs.files["/r/recipe.yaml"] = text;
    fs.files["/r/frag.yaml"] = "nodes:\n  f:\n    stage: text\n";
    fs.files["/r/data.txt"] = "d";
    Diagnostics d;
    std::optional<Recipe> r;
    ASSERT_NO_THROW(r = load_recipe("/r/recipe.yaml", reg, fs, d)) << text;
    if (r) {
      ++loaded;
      EXPECT_TRUE(d.empty());
    } else {
      ++rejected;
      ASSERT_FALSE(d.empty()) << "rejected without a message:\n" << text;
      for (const auto& diag : d.all()) ASSERT_NE(diag.message, "") << text;
    }
  }
  // Both outcomes occur: the fuzzer reaches the checks, not only the YAML parser.
  EXPECT_GT(loaded, 30);
  EXPECT_GT(rejected, 100);
}

}  // namespace
}  // namespace sylva
