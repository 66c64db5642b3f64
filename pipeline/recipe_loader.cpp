// Recipe loading in passes, each reporting every problem it finds before the next one runs:
//   1. read the recipe and its `include:` fragments into RawNode trees (yaml_tree.cpp);
//   2. check the top-level keys, collect the matrix, defaults and node entries (this file);
//   3. expand each node over the matrix variables its name uses, substituting `${var}`
//      (recipe_matrix.cpp, recipe_vars.cpp);
//   4. check each node: name, stage, `with:` parameters against the stage schema, defaults
//      (node_checker.cpp, param_checker.cpp);
//   5. resolve `needs` patterns and check input types and counts (needs_resolver.cpp);
//   6. prove the graph acyclic (graph.cpp), printing a cycle when there is one.
#include "pipeline/recipe_loader.h"

#include <algorithm>
#include <charconv>
#include <set>

#include "pipeline/graph.h"
#include "pipeline/needs_resolver.h"
#include "pipeline/node_checker.h"
#include "pipeline/param_checker.h"
#include "pipeline/project_root.h"
#include "pipeline/recipe_matrix.h"
#include "pipeline/recipe_vars.h"
#include "pipeline/yaml_tree.h"

namespace sylva {

bool is_valid_name(std::string_view name) {
  if (name.empty() || name.size() > 128 || name == "." || name == "..") return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

const NodeDecl* Recipe::find(std::string_view node) const {
  const std::size_t i = index_of(node);
  return i < nodes.size() ? &nodes[i] : nullptr;
}

std::size_t Recipe::index_of(std::string_view node) const {
  if (index_.size() != nodes.size()) {  // not indexed (hand-built in a test): scan
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (nodes[i].name == node) return i;
    return nodes.size();
  }
  auto it = index_.find(std::string(node));
  return it == index_.end() ? nodes.size() : it->second;
}

void Recipe::reindex() {
  index_.clear();
  for (std::size_t i = 0; i < nodes.size(); ++i) index_.emplace(nodes[i].name, i);
}

namespace {

namespace fs = std::filesystem;

// Recipe names that would clash with what shares the output root (out/cache, CMake's
// out/build, out/npm, out/test-images): refused, so publishing into out/<recipe>/ can never
// replace or delete them.
bool reserved_recipe_name(const std::string& n) {
  static const std::set<std::string> kReserved = {"cache", "build", "npm", "test-images", "tmp"};
  return n.front() == '.' || kReserved.count(n) > 0;
}

// ---- the loader ----------------------------------------------------------------------

struct NodeEntry {
  RawNode key;
  RawNode body;
};

class Loader {
 public:
  Loader(const StageRegistry& reg, FileSystem& fs, Diagnostics& diags, const LoadOptions& options)
      : fs_(fs),
        diags_(diags),
        options_(options),
        yaml_(fs, src_, diags, options.parse_cache_dir,
              YamlLimits{options.limits.file_bytes, options.limits.yaml_nodes, options.limits.include_depth}),
        params_(fs, src_, diags, project_root_),
        nodes_(reg, src_, diags, params_, defaults_, recipe_.nodes) {}

  std::optional<Recipe> load(const fs::path& file) {
    recipe_.file = file;
    auto root = yaml_.read_unresolved(file);
    if (!root) return std::nullopt;
    if (!choose_root(*root, file)) return std::nullopt;
    yaml_.set_root(&project_root_);
    if (!yaml_.resolve(*root, file)) return std::nullopt;
    read_top(*root, /*is_root=*/true, {});
    // Node checks run even after top-level errors so one run reports as much as it can.
    recipe_.nodes.reserve(entries_.size());
    nodes_.reserve(entries_.size());
    expand_nodes();
    nodes_.check_defaults();
    if (!diags_.empty()) return std::nullopt;
    recipe_.reindex();
    resolve_needs(recipe_, nodes_.needs_raw(), nodes_.with_raw(), defaults_, src_, diags_);
    if (!diags_.empty()) return std::nullopt;
    if (auto cycle = find_cycle(recipe_)) {
      std::string chain;
      for (std::size_t i : *cycle) chain += recipe_.nodes[i].name + " -> ";
      chain += recipe_.nodes[cycle->front()].name;
      src_.error(diags_, recipe_.nodes[cycle->front()].loc, "dependency cycle: " + chain);
      return std::nullopt;
    }
    return std::move(recipe_);
  }

 private:
  void err(const SourceLoc& loc, std::string msg) { src_.error(diags_, loc, std::move(msg)); }

  // The project root: the directories the recipe's `root:` names (relative to the recipe),
  // else its directory; a root given by the caller (--root) bounds them. Unconfined when
  // options_.confine is false.
  bool choose_root(const RawNode& top, const fs::path& file) {
    if (!options_.confine) return true;
    const fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    const RawNode* declared = nullptr;
    if (top.is_map())
      for (const auto& [k, v] : top.entries)
        if (k.is_scalar() && k.text == "root") declared = &v;
    std::vector<fs::path> roots;
    if (declared) {
      std::vector<const RawNode*> items;
      if (declared->is_scalar())
        items.push_back(declared);
      else if (declared->is_seq())
        for (const auto& i : declared->items) items.push_back(&i);
      bool ok = !items.empty();
      for (const RawNode* i : items) ok = ok && i->is_scalar() && !i->text.empty();
      if (!ok) {
        err(declared->loc, "'root' must be a directory or a list of directories (relative to the recipe)");
        return false;
      }
      for (const RawNode* i : items) {
        fs::path d = i->text;
        if (d.is_relative()) d = dir / d;
        d = d.lexically_normal();
        if (!d.has_filename() && d.has_relative_path()) d = d.parent_path();  // "a/b/" -> "a/b"
        // A root that does not exist (optional data not downloaded) is kept: its files are then
        // reported as missing, not as outside the project.
        auto st = fs_.stat(d);
        if (st && !st->is_dir) {
          err(i->loc, "'root' names '" + excerpt(d.string(), 200) + "', which is not a directory");
          return false;
        }
        if (!options_.root.empty() && !ProjectRoot(options_.root).contains(d)) {
          err(i->loc, "'root' names '" + excerpt(d.string(), 200) + "', outside the root given by --root ('" +
                          excerpt(options_.root.string(), 200) + "')");
          return false;
        }
        roots.push_back(d);
      }
    } else {
      roots.push_back(options_.root.empty() ? dir : options_.root);
    }
    project_root_ = ProjectRoot(roots);
    return true;
  }

  // Top-level keys of the recipe or of an included fragment.
  // The node entries are moved out of `root` (a 10,000-node recipe is not copied).
  void read_top(RawNode& root, bool is_root, std::vector<std::string> include_stack) {
    const std::string file = root.loc.file();
    if (!root.is_map()) {
      err(root.loc, std::string(is_root ? "a recipe" : "an included recipe fragment") +
                        " must be a map, got a " + root.kind_name());
      return;
    }
    static const std::vector<std::string> kRootKeys = {"version", "name",     "description", "root",
                                                       "include", "defaults", "matrix",      "nodes"};
    static const std::vector<std::string> kFragmentKeys = {"description", "include", "defaults", "matrix",
                                                           "nodes"};
    const auto& allowed = is_root ? kRootKeys : kFragmentKeys;
    std::set<std::string> seen;
    bool have_version = false, have_name = false;
    for (auto& [k, v] : root.entries) {
      if (!k.is_scalar()) {
        err(k.loc, "keys must be plain names");
        continue;
      }
      if (std::find(allowed.begin(), allowed.end(), k.text) == allowed.end()) {
        const bool root_only = std::find(kRootKeys.begin(), kRootKeys.end(), k.text) != kRootKeys.end();
        err(k.loc, root_only ? "'" + k.text + "' is only allowed in the top-level recipe"
                             : "unknown key '" + excerpt(k.text) + "'" + did_you_mean(k.text, allowed));
        continue;
      }
      if (!seen.insert(k.text).second) {
        err(k.loc, "duplicate key '" + k.text + "'");
        continue;
      }
      if (k.text == "version") {
        have_version = true;
        if (!v.is_scalar() || v.text != "1")
          err(v.loc, "unsupported recipe version '" +
                         (v.is_scalar() ? excerpt(v.text) : std::string(v.kind_name())) +
                         "' (this sylva reads version 1)");
      } else if (k.text == "root") {
        // chosen before anything was read (choose_root)
      } else if (k.text == "name") {
        have_name = true;
        if (!v.is_scalar() || !is_valid_name(v.text))
          err(v.loc, "invalid recipe name '" + excerpt(v.text) + "': use letters, digits, '_', '-' and '.'");
        else if (reserved_recipe_name(v.text))
          err(v.loc,
              "reserved recipe name '" + v.text +
                  "': out/cache, out/build, out/npm, out/test-images, out/tmp and names starting with '.' "
                  "belong to sylva and the build; choose another name");
        else
          recipe_.name = v.text;
      } else if (k.text == "include") {
        read_includes(v, include_stack);
      } else if (k.text == "defaults") {
        read_defaults(v);
      } else if (k.text == "matrix") {
        read_matrix(v, global_matrix_, src_, diags_);
      } else if (k.text == "nodes") {
        if (v.is_null()) continue;
        if (!v.is_map()) {
          err(v.loc, "'nodes' must be a map of node name to node, got a " + std::string(v.kind_name()));
          continue;
        }
        for (auto& [nk, nv] : v.entries) entries_.push_back({std::move(nk), std::move(nv)});
      }
    }
    if (is_root && !have_version) err({file, 1, 1}, "missing required key 'version'");
    if (is_root && !have_name) err({file, 1, 1}, "missing required key 'name'");
  }

  void read_includes(const RawNode& v, std::vector<std::string> stack) {
    std::vector<RawNode> list;
    if (v.is_scalar())
      list.push_back(v);
    else if (v.is_seq())
      list = v.items;
    else {
      err(v.loc, "'include' must be a file name or a list of file names");
      return;
    }
    for (const auto& item : list) {
      if (!item.is_scalar()) {
        err(item.loc, "'include' entries must be file names");
        continue;
      }
      const fs::path target = (fs::path(item.loc.file()).parent_path() / item.text).lexically_normal();
      if (!project_root_.contains(target)) {
        err(item.loc, "include " + project_root_.outside_message(target));
        continue;
      }
      if (stack.size() >= options_.limits.include_depth) {
        err(item.loc, "includes nested deeper than " + std::to_string(options_.limits.include_depth) +
                          " files; raise the limit with --limit include-depth=N");
        continue;
      }
      if (std::find(stack.begin(), stack.end(), target.string()) != stack.end() ||
          target.string() == fs::path(v.loc.file()).lexically_normal().string()) {
        err(item.loc, "include cycle: '" + target.string() + "' is already being read");
        continue;
      }
      auto frag = yaml_.read(target, item.loc);
      if (!frag) continue;
      auto next = stack;
      next.push_back(fs::path(v.loc.file()).lexically_normal().string());
      read_top(*frag, /*is_root=*/false, next);
    }
  }

  void read_defaults(const RawNode& v) {
    if (v.is_null()) return;
    if (!v.is_map()) {
      err(v.loc, "'defaults' must be a map of parameter name to value");
      return;
    }
    for (const auto& [k, val] : v.entries) {
      if (defaults_.count(k.text)) {
        err(k.loc, "duplicate default '" + k.text + "' (first set at " +
                       defaults_.at(k.text).first.loc.prefix() + ")");
        continue;
      }
      defaults_.emplace(k.text, std::make_pair(k, val));
    }
  }

  // Pass 3 + 4: expansion and per-node checks.
  void expand_nodes() {
    for (const auto& e : entries_) {
      if (diags_.full()) return;  // enough errors reported; the rest are not looked at
      if (too_many_nodes()) return;
      if (!expand_node(e)) return;
    }
  }

  // Checks the node entry `e`, once per combination of the matrix variables its name uses;
  // false when the checks must stop (too many errors or nodes).
  bool expand_node(const NodeEntry& e) {
    // A node-level `matrix:` adds or overrides variables for this node only.
    const std::optional<NodeMatrix> local = node_matrix(e.body, global_matrix_, src_, diags_);
    const RawNode& body = local ? local->body : e.body;
    const std::vector<MatrixVar>& matrix = local ? local->matrix : global_matrix_;
    std::vector<VarRef> name_vars, body_vars;
    const std::size_t errors_before = diags_.size();
    bool dollar = false;
    collect_vars(e.key, name_vars, src_, diags_, &dollar);
    collect_vars(body, body_vars, src_, diags_, &dollar);
    if (diags_.size() != errors_before) return true;  // malformed ${...}: nothing to expand
    if (!dollar) {  // nothing to substitute: the common case, checked without copying the node
      nodes_.check(e.key, body);
      return true;
    }
    auto used = matrix_vars_used(e.key.text, name_vars, body_vars, matrix, src_, diags_);
    if (!used) return true;
    // Checked before expanding: a matrix of 10^8 combinations is refused at once.
    const std::uint64_t combinations = matrix_combinations(*used, options_.limits.matrix);
    // A variable whose every value was refused (reported above) has no values: nothing to expand.
    if (combinations == 0) return true;
    if (combinations > options_.limits.matrix) {
      err(e.key.loc, "node '" + excerpt(e.key.text, 80) + "' expands to more than " +
                         std::to_string(options_.limits.matrix) +
                         " nodes over its matrix; raise the limit with --limit matrix=N");
      return true;
    }
    return for_each_combination(*used, [&](const std::map<std::string, std::string>& vars) {
      if (diags_.full() || too_many_nodes()) return false;
      nodes_.check(substitute_vars(e.key, vars), substitute_vars(body, vars));
      return true;
    });
  }

  // True (once reported) when the recipe has more nodes than options_.limits.nodes.
  bool too_many_nodes() {
    if (nodes_.names_seen() < options_.limits.nodes) return false;
    if (!nodes_reported_)
      err({recipe_.file.string(), 1, 1}, "the recipe has more than " + std::to_string(options_.limits.nodes) +
                                             " nodes; raise the limit with --limit nodes=N");
    nodes_reported_ = true;
    return true;
  }

  FileSystem& fs_;
  Diagnostics& diags_;
  const LoadOptions& options_;
  ProjectRoot project_root_;  // unconfined until choose_root()
  bool nodes_reported_ = false;
  SourceFiles src_;
  YamlReader yaml_;
  ParamChecker params_;
  Recipe recipe_;
  std::vector<MatrixVar> global_matrix_;
  RecipeDefaults defaults_;
  std::vector<NodeEntry> entries_;
  NodeChecker nodes_;
};

}  // namespace

std::optional<Recipe> load_recipe(const fs::path& file, const StageRegistry& registry, FileSystem& fs,
                                  Diagnostics& diags, const LoadOptions& options) {
  Loader loader(registry, fs, diags, options);
  return loader.load(file);
}

std::optional<Recipe> load_recipe(const fs::path& file, const StageRegistry& registry, FileSystem& fs,
                                  Diagnostics& diags, const fs::path& parse_cache_dir) {
  LoadOptions options;
  options.parse_cache_dir = parse_cache_dir;
  return load_recipe(file, registry, fs, diags, options);
}

std::optional<std::string> set_limit(LoadLimits& limits, std::string_view spec) {
  const auto eq = spec.find('=');
  const std::string name(spec.substr(0, eq));
  std::uint64_t* slot = name == "file-bytes"      ? &limits.file_bytes
                        : name == "yaml-nodes"    ? &limits.yaml_nodes
                        : name == "include-depth" ? &limits.include_depth
                        : name == "matrix"        ? &limits.matrix
                        : name == "nodes"         ? &limits.nodes
                        : name == "errors"        ? &limits.errors
                                                  : nullptr;
  if (!slot)
    return "unknown limit '" + excerpt(name) +
           "' (file-bytes, yaml-nodes, include-depth, matrix, nodes, errors)";
  std::uint64_t v = 0;
  const std::string_view num = eq == std::string_view::npos ? std::string_view() : spec.substr(eq + 1);
  auto [p, ec] = std::from_chars(num.data(), num.data() + num.size(), v);
  if (num.empty() || ec != std::errc() || p != num.data() + num.size() || v == 0)
    return "limit '" + name + "' needs a positive integer, as in " + name + "=1000";
  *slot = v;
  return std::nullopt;
}

}  // namespace sylva
