// YAML recipe → checked Recipe. The format is specified in docs/recipes.md.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "pipeline/diagnostic.h"
#include "pipeline/filesystem.h"
#include "pipeline/recipe.h"
#include "pipeline/registry.h"

namespace sylva {

// What one recipe may cost to load (docs/recipes.md, "Limits"): each exceeded limit is one
// clear error, never a hang or an exhausted memory. Raised with `--limit NAME=N`.
struct LoadLimits {
  std::uint64_t file_bytes = 16u << 20;                 // file-bytes: each recipe or included file
  std::uint64_t yaml_nodes = 1'000'000;                 // yaml-nodes: nodes of one file, aliases expanded
  std::uint64_t include_depth = 16;                     // include-depth: nested `include:` / `!include`
  std::uint64_t matrix = 10'000;                        // matrix: nodes one matrix entry expands to
  std::uint64_t nodes = 100'000;                        // nodes: nodes of the whole recipe
  std::uint64_t errors = Diagnostics::kDefaultMaxKept;  // errors: errors reported
};

// Sets one limit from "name=N" (names as above); nullopt on success, else what is wrong.
std::optional<std::string> set_limit(LoadLimits& limits, std::string_view spec);

struct LoadOptions {
  // Keeps parsed YAML trees between runs (yaml_tree.h, YamlReader); empty: none.
  std::filesystem::path parse_cache_dir;
  // Paths must lie inside the project root (pipeline/project_root.h): the recipe's directory,
  // or the directory its `root:` key names. false: any path (trusted recipes only).
  bool confine = true;
  // A root given by whoever runs sylva (--root): the project root unless the recipe's `root:`
  // names a directory inside it (one outside it is an error). Empty: none.
  std::filesystem::path root;
  LoadLimits limits;
};

// Loads and validates `file`. On any problem, returns nullopt with every problem found in
// `diags` (each at its file:line:col, with the source line for a caret display).
std::optional<Recipe> load_recipe(const std::filesystem::path& file, const StageRegistry& registry,
                                  FileSystem& fs, Diagnostics& diags, const LoadOptions& options);
// The same with default options and a parse cache directory.
std::optional<Recipe> load_recipe(const std::filesystem::path& file, const StageRegistry& registry,
                                  FileSystem& fs, Diagnostics& diags,
                                  const std::filesystem::path& parse_cache_dir = {});

}  // namespace sylva
