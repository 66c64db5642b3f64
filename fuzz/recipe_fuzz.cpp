// libFuzzer target: the recipe loader (YAML parsing, includes, matrix, defaults, parameter
// checks; docs/recipes.md). The input is the recipe; it may include frag.yaml and read data.txt
// from an in-memory file system. Contract: load_recipe never throws; a rejected recipe has at
// least one diagnostic, each with a message; an accepted one has none.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_filesystem.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  static StageRegistry* registry = [] {
    auto* reg = new StageRegistry;
    test::register_test_stages(*reg, nullptr);
    return reg;
  }();
  test::FakeFileSystem fs;
  fs.files["/r/recipe.yaml"] = std::string(reinterpret_cast<const char*>(data), size);
  fs.files["/r/frag.yaml"] = "nodes:\n  f:\n    stage: text\n";
  fs.files["/r/data.txt"] = "d";
  Diagnostics diags;
  std::optional<Recipe> recipe;
  try {
    recipe = load_recipe("/r/recipe.yaml", *registry, fs, diags);
  } catch (const std::exception& e) {
    fuzz::fail(std::string("load_recipe threw: ") + e.what());
  } catch (...) {
    fuzz::fail("load_recipe threw a non-std exception");
  }
  if (recipe && !diags.empty()) fuzz::fail("accepted recipe with diagnostics");
  if (!recipe && diags.empty()) fuzz::fail("rejected recipe without a diagnostic");
  for (const auto& d : diags.all())
    if (d.message.empty()) fuzz::fail("diagnostic without a message");
  return 0;
}
