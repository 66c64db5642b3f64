// A loaded, fully checked recipe: what `sylva build` runs.
//
// Loading (recipe_loader.h) turns YAML into this: includes merged, the matrix expanded,
// `${var}` substituted, every parameter type- and range-checked against its stage's schema with
// defaults filled in, `needs` patterns resolved to node names, input types checked, and the
// dependency graph proven acyclic. Nothing downstream re-validates.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "pipeline/diagnostic.h"
#include "pipeline/filesystem.h"
#include "pipeline/stage.h"
#include "pipeline/value.h"

namespace sylva {

struct NodeDecl {
  std::string name;  // [A-Za-z0-9_.-]+, not "." or "..": safe as a directory name
  SourceLoc loc;     // the node's key in the recipe
  const Stage* stage = nullptr;
  std::vector<std::string> needs;  // upstream node names: pattern order, matches sorted, unique
  Value::Object params;            // complete (defaults filled), typed
  std::map<std::string, std::filesystem::path> files;  // kPath/kDir parameter -> resolved path
  std::map<std::string, FileInfo> file_stats;          // their stat when the recipe was loaded
};

struct Recipe {
  std::string name;             // [A-Za-z0-9_.-]+: outputs go to out/<name>/
  std::filesystem::path file;   // the top-level recipe file
  std::vector<NodeDecl> nodes;  // declaration order, matrix expansions in matrix order

  const NodeDecl* find(std::string_view node) const;
  std::size_t index_of(std::string_view node) const;  // nodes.size() if absent
  // Rebuilds the name index; call after changing `nodes` (the loader does).
  void reindex();

 private:
  std::unordered_map<std::string, std::size_t> index_;
};

// True if `name` may be used as a node or recipe name (and therefore as a directory name).
bool is_valid_name(std::string_view name);

}  // namespace sylva
