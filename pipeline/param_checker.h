// Recipe values -> typed parameter values, checked against a stage's parameter schema
// (pipeline/param.h; docs/recipes.md, "Parameters"). Every problem is reported at the value's
// file:line:col, in the exact words the recipe tests compare.
#pragma once

#include <optional>
#include <string>

#include "pipeline/diagnostic.h"
#include "pipeline/filesystem.h"
#include "pipeline/param.h"
#include "pipeline/project_root.h"
#include "pipeline/recipe.h"
#include "pipeline/value.h"
#include "pipeline/yaml_tree.h"

namespace sylva {

class ParamChecker {
 public:
  // All four are referenced, not owned; `root` may change after construction (the loader chooses
  // the project root once it has read the recipe's `root:` key).
  ParamChecker(FileSystem& fs, const SourceFiles& src, Diagnostics& diags, const ProjectRoot& root)
      : fs_(fs), src_(src), diags_(diags), root_(root) {}

  // Converts `raw` to `spec`'s type; reports and returns nullopt on any problem. `what` names the
  // value in messages ("parameter 'x'", "default 'x'"; nested values append ".field" or "[i]").
  // A kPath/kDir value is resolved against the directory of the YAML file that wrote it, must lie
  // inside the project root and must exist as a file or directory (as the type says).
  // `files` (may be null) receives those resolved paths and their stats, keyed by `spec.name`.
  std::optional<Value> convert(const ParamSpec& spec, const RawNode& raw, const std::string& what,
                               NodeDecl* files);

 private:
  std::optional<Value> convert_bool(const ParamSpec& spec, const RawNode& raw, const std::string& what);
  std::optional<Value> convert_int(const ParamSpec& spec, const RawNode& raw, const std::string& what);
  std::optional<Value> convert_real(const ParamSpec& spec, const RawNode& raw, const std::string& what);
  std::optional<Value> convert_enum(const ParamSpec& spec, const RawNode& raw, const std::string& what);
  std::optional<Value> convert_path(const ParamSpec& spec, const RawNode& raw, const std::string& what,
                                    NodeDecl* files);
  // kIntList, kRealList, kStringList: a list of scalars of the element type.
  std::optional<Value> convert_scalar_list(const ParamSpec& spec, const RawNode& raw,
                                           const std::string& what);
  std::optional<Value> convert_object(const ParamSpec& spec, const RawNode& raw, const std::string& what,
                                      NodeDecl* files);
  std::optional<Value> convert_object_list(const ParamSpec& spec, const RawNode& raw,
                                           const std::string& what);
  // kMap: names to real numbers.
  std::optional<Value> convert_map(const ParamSpec& spec, const RawNode& raw, const std::string& what);

  // Converts each item of the list `raw` as `elem`; nullopt (all reported) if any fails.
  std::optional<Value::List> convert_items(const ParamSpec& elem, const RawNode& raw,
                                           const std::string& what);
  // Reports and returns false when the list `raw` has fewer or more items than `spec` allows.
  bool check_item_count(const ParamSpec& spec, const RawNode& raw, const std::string& what);
  bool in_range(const ParamSpec& spec, double v, const RawNode& raw, const std::string& what);
  std::optional<Value> wrong(const ParamSpec& spec, const RawNode& raw, const std::string& what);

  FileSystem& fs_;
  const SourceFiles& src_;
  Diagnostics& diags_;
  const ProjectRoot& root_;
};

}  // namespace sylva
