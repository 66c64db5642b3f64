// Parameter schemas: what a stage accepts under `with:`.
//
// Every stage declares one ParamSpec per parameter: its type, default (absent = required),
// inclusive numeric range, allowed choices, and a one-line doc shown by `sylva stages`.
// The recipe loader checks every `with:` entry against these and reports problems at the
// entry's file:line:col; stages then read values that are guaranteed to be present and valid.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/value.h"

namespace sylva {

enum class ParamType {
  kBool,
  kInt,
  kReal,
  kString,
  kEnum,  // string restricted to `choices`
  kPath,  // a file the node reads; relative to the YAML file that names it; hashed by content
  kDir,   // a directory the node reads (every regular file below it is hashed by content)
  kIntList,
  kRealList,
  kStringList,
  kObject,      // nested map with its own `fields`
  kMap,         // free string keys -> real values (e.g. density_per_ha: {oak: 10})
  kObjectList,  // list of objects, each checked against `fields` (no kPath/kDir fields)
};

const char* param_type_name(ParamType t);

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::kReal;
  Value default_value;                              // null => required
  std::optional<double> min, max;                   // inclusive; applies to numbers and to list elements
  std::vector<std::string> choices;                 // kEnum only
  std::optional<std::size_t> min_items, max_items;  // list types only
  std::vector<ParamSpec> fields;                    // kObject and kObjectList only
  std::string doc;
  // Constraints the recipe loader checks (at file:line:col, before any node runs).
  bool power_of_two = false;  // kInt: 1, 2, 4, 8, ...
  bool increasing = false;    // kIntList/kRealList: each item greater than the one before
  // kPath only: extensions (".gltf", with the dot, lower case) whose file brings its folder
  // along; see with_folder_for() and param_folder().
  std::vector<std::string> folder_for;

  bool required() const { return default_value.is_null(); }

  // Chainable modifiers, used on the temporaries Param:: returns.
  ParamSpec range(std::optional<double> lo, std::optional<double> hi) && {
    min = lo;
    max = hi;
    return std::move(*this);
  }
  ParamSpec items(std::optional<std::size_t> lo, std::optional<std::size_t> hi) && {
    min_items = lo;
    max_items = hi;
    return std::move(*this);
  }
  ParamSpec describe(std::string text) && {
    doc = std::move(text);
    return std::move(*this);
  }
  ParamSpec require_power_of_two() && {
    power_of_two = true;
    return std::move(*this);
  }
  ParamSpec require_increasing() && {
    increasing = true;
    return std::move(*this);
  }
  // kPath: when the named file's extension is one of `extensions` (compared without regard to
  // case), the file's whole parent directory is part of the node's input, as if a kDir
  // parameter named it: every regular file below it enters the action key (beside the file's
  // own digest) and ctx.files() may read any of them. For model files that name companions by
  // relative path (a .gltf's .bin and textures, an .obj's .mtl). Other extensions: the file
  // alone, as without this. The folder may hold at most kMaxFolderFiles files.
  ParamSpec with_folder_for(std::vector<std::string> extensions) && {
    folder_for = std::move(extensions);
    return std::move(*this);
  }
};

// The most regular files a with_folder_for() folder may hold (every subdirectory counted): a
// model at the top of a large tree would otherwise hash all of it into every key. More is a
// recipe error at the parameter, and (a folder that grew since loading) a node failure when
// the key is computed ("... holds more than 2000 files ...").
inline constexpr std::size_t kMaxFolderFiles = 2000;

// The folder `file` brings along under `spec` (its parent directory), or nullopt when spec has
// no with_folder_for() extension matching file's (ASCII case-insensitive).
std::optional<std::filesystem::path> param_folder(const ParamSpec& spec, const std::filesystem::path& file);

// Fluent builders keep stage declarations short and readable:
//   Param::real("pixel_error", 0.5).range(0.01, 100).doc("permitted pixel error δ (px)")
struct Param {
  static ParamSpec boolean(std::string name, bool def);
  static ParamSpec integer(std::string name, std::optional<std::int64_t> def = std::nullopt);
  static ParamSpec real(std::string name, std::optional<double> def = std::nullopt);
  static ParamSpec string(std::string name, std::optional<std::string> def = std::nullopt);
  static ParamSpec choice(std::string name, std::vector<std::string> choices,
                          std::optional<std::string> def = std::nullopt);
  static ParamSpec path(std::string name);  // always required
  static ParamSpec dir(std::string name);   // always required
  static ParamSpec real_list(std::string name, std::optional<Value::List> def = std::nullopt);
  static ParamSpec int_list(std::string name, std::optional<Value::List> def = std::nullopt);
  static ParamSpec string_list(std::string name, std::optional<Value::List> def = std::nullopt);
  static ParamSpec object(std::string name, std::vector<ParamSpec> fields);
  static ParamSpec real_map(std::string name, std::optional<Value::Object> def = std::nullopt);
  // A list of objects with `fields` (e.g. species: [{name: oak, density_per_ha: 10}, ...]);
  // the default is the empty list. Fields may not be paths or directories.
  static ParamSpec object_list(std::string name, std::vector<ParamSpec> fields);
};

}  // namespace sylva
