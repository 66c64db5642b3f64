// YAML recipe → checked Recipe. The format is specified in docs/recipes.md.
#pragma once

#include <filesystem>
#include <optional>

#include "pipeline/diagnostic.h"
#include "pipeline/filesystem.h"
#include "pipeline/recipe.h"
#include "pipeline/registry.h"

namespace sylva {

// Loads and validates `file`. On any problem, returns nullopt with every problem found in
// `diags` (each at its file:line:col, with the source line for a caret display).
// `parse_cache_dir` (optional) keeps parsed YAML trees between runs (yaml_tree.h, YamlReader).
std::optional<Recipe> load_recipe(const std::filesystem::path& file, const StageRegistry& registry,
                                  FileSystem& fs, Diagnostics& diags,
                                  const std::filesystem::path& parse_cache_dir = {});

}  // namespace sylva
