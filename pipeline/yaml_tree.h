// YAML documents as plain trees that remember where every scalar came from.
//
// The recipe loader works on RawNode instead of YAML::Node because it rewrites the tree
// (matrix substitution, `!include` inlining) and must still report every error at the
// original file:line:col. Parsing goes through yaml-cpp; `!include path` on any value is
// replaced by the root of that file (resolved relative to the including file).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/diagnostic.h"
#include "pipeline/filesystem.h"
#include "pipeline/project_root.h"

namespace sylva {

struct RawNode {
  enum class Kind { kNull, kScalar, kSeq, kMap };
  Kind kind = Kind::kNull;
  std::string text;                                  // kScalar
  std::vector<RawNode> items;                        // kSeq
  std::vector<std::pair<RawNode, RawNode>> entries;  // kMap, in file order (duplicates kept)
  SourceLoc loc;
  bool include = false;  // a `!include` scalar not yet replaced (only inside YamlReader)

  // Defined in the .cpp, where RawNode is complete: clang (with libstdc++ 12) cannot check the
  // implicit constructor of `entries` (pairs of the still incomplete RawNode) inside the class.
  RawNode();

  bool is_scalar() const { return kind == Kind::kScalar; }
  bool is_seq() const { return kind == Kind::kSeq; }
  bool is_map() const { return kind == Kind::kMap; }
  bool is_null() const { return kind == Kind::kNull; }
  const char* kind_name() const;  // "null", "scalar", "list", "map"
};

// Remembers the text of every file read, so diagnostics can show the offending line.
class SourceFiles {
 public:
  void add(const std::string& file, std::string text);
  std::string line(const std::string& file, int line) const;  // "" if unknown
  // Adds a diagnostic at `loc` with its source line attached.
  void error(Diagnostics& diags, const SourceLoc& loc, std::string message) const;

 private:
  std::map<std::string, std::string> texts_;
};

// Parsing a 10,000-node recipe with yaml-cpp costs more than the no-op build it precedes, so
// the reader can keep each file's parsed tree (before `!include` is resolved) in
// `parse_cache_dir`, one entry per file path, used only while the file's bytes are the same
// (their SHA-256 is in the entry). A missing, stale or damaged entry just means parsing again.
//
// Limits (each exceeded one is a diagnostic, docs/recipes.md "Limits"): a file of more than
// `file_bytes` is not read, one that expands (aliases included: the "billion laughs") to more
// than `yaml_nodes` nodes is not converted, `!include` nests at most `include_depth` deep; YAML
// nested deeper than kMaxYamlDepth is refused.
// Mappings and sequences nest at most this deep in one file (a recipe needs about ten levels).
inline constexpr int kMaxYamlDepth = 128;

struct YamlLimits {
  std::uint64_t file_bytes = 16u << 20;
  std::uint64_t yaml_nodes = 1'000'000;
  std::uint64_t include_depth = 16;
};

class YamlReader {
 public:
  YamlReader(FileSystem& fs, SourceFiles& sources, Diagnostics& diags,
             std::filesystem::path parse_cache_dir = {}, YamlLimits limits = {})
      : fs_(fs),
        sources_(sources),
        diags_(diags),
        parse_cache_dir_(std::move(parse_cache_dir)),
        limits_(limits) {}

  // Every `!include` target must lie inside `root` (not owned; default: unconfined).
  void set_root(const ProjectRoot* root) { root_ = root; }

  // Parses `file` (a path as the user wrote it) and resolves its `!include`s. On failure adds
  // a diagnostic located at `from` (the place that named the file; empty for the top-level
  // recipe) and returns nullopt.
  std::optional<RawNode> read(const std::filesystem::path& file, const SourceLoc& from = {});
  // The two halves of read(): parse only (the recipe's `root:` key is needed before any
  // `!include` is followed), then resolve the `!include`s of a tree read from `file`.
  std::optional<RawNode> read_unresolved(const std::filesystem::path& file, const SourceLoc& from = {});
  bool resolve(RawNode& tree, const std::filesystem::path& file);

 private:
  std::optional<RawNode> read_impl(const std::filesystem::path& file, const SourceLoc& from, bool resolve);
  std::optional<RawNode> parse(const std::string& name, const std::string& text);
  bool resolve_includes(RawNode& n, const std::filesystem::path& file);

  FileSystem& fs_;
  SourceFiles& sources_;
  Diagnostics& diags_;
  std::filesystem::path parse_cache_dir_;
  YamlLimits limits_;
  const ProjectRoot* root_ = nullptr;
  std::vector<std::string> stack_;  // files being read (include cycle detection)
};

}  // namespace sylva
