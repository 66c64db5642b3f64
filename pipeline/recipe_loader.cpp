// Recipe loading in passes, each reporting every problem it finds before the next one runs:
//   1. read the recipe and its `include:` fragments into RawNode trees (yaml_tree.cpp);
//   2. check the top-level keys, collect the matrix, defaults and node entries;
//   3. expand each node over the matrix variables its name uses, substituting `${var}`;
//   4. check each node: name, stage, `with:` parameters against the stage schema, defaults;
//   5. resolve `needs` patterns and check input types and counts;
//   6. prove the graph acyclic (graph.cpp), printing a cycle when there is one.
#include "pipeline/recipe_loader.h"

#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <unordered_map>

#include "pipeline/graph.h"
#include "pipeline/project_root.h"
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

// ---- `${var}` substitution -------------------------------------------------------------

struct VarRef {
  std::string name;
  SourceLoc loc;
};

// Variable references in `text` ("$${" is a literal "${"). Unterminated "${" is reported.
std::vector<std::string> vars_in(const std::string& text, bool* malformed) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] == '$' && text[i + 1] == '$') {
      ++i;
      continue;
    }
    if (text[i] == '$' && text[i + 1] == '{') {
      const auto end = text.find('}', i + 2);
      if (end == std::string::npos) {
        *malformed = true;
        return out;
      }
      out.push_back(text.substr(i + 2, end - i - 2));
      i = end;
    }
  }
  return out;
}

std::string substitute_text(const std::string& text, const std::map<std::string, std::string>& vars) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '$' && i + 1 < text.size() && text[i + 1] == '$') {
      out += '$';
      ++i;
    } else if (text[i] == '$' && i + 1 < text.size() && text[i + 1] == '{') {
      const auto end = text.find('}', i + 2);
      out += vars.at(text.substr(i + 2, end - i - 2));
      i = end;
    } else {
      out += text[i];
    }
  }
  return out;
}

// `dollar` is set if any scalar contains '$' (then substitution can change text: "$$" -> "$").
void collect_vars(const RawNode& n, std::vector<VarRef>& out, const SourceFiles& src, Diagnostics& diags,
                  bool* dollar) {
  if (n.is_scalar() && n.text.find('$') != std::string::npos) {
    *dollar = true;
    bool malformed = false;
    for (auto& v : vars_in(n.text, &malformed)) {
      const bool ident = !v.empty() && std::all_of(v.begin(), v.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
      });
      if (!ident) src.error(diags, n.loc, "invalid variable name '${" + v + "}' in '" + n.text + "'");
      out.push_back({v, n.loc});
    }
    if (malformed) src.error(diags, n.loc, "unterminated '${' in '" + n.text + "'");
  }
  for (const auto& i : n.items) collect_vars(i, out, src, diags, dollar);
  for (const auto& [k, v] : n.entries) {
    collect_vars(k, out, src, diags, dollar);
    collect_vars(v, out, src, diags, dollar);
  }
}

RawNode substitute(const RawNode& n, const std::map<std::string, std::string>& vars) {
  RawNode r = n;
  if (r.is_scalar()) r.text = substitute_text(r.text, vars);
  for (auto& i : r.items) i = substitute(i, vars);
  for (auto& [k, v] : r.entries) {
    k = substitute(k, vars);
    v = substitute(v, vars);
  }
  return r;
}

// ---- parameter conversion --------------------------------------------------------------

// (directory of `file`) / `text`, lexically normal; `text` as is when absolute. Plain paths
// (no ".", "..", empty element or trailing "/") are joined as strings: a 10,000-file recipe
// does this once per file.
fs::path joined_normal(const std::string& file, const std::string& text) {
  std::string s;
  if (!text.empty() && text[0] == '/') {
    s = text;
  } else {
    const std::size_t slash = file.rfind('/');
    if (slash != std::string::npos) s.assign(file, 0, slash + 1);
    s += text;
  }
  bool plain = !s.empty() && s.back() != '/';
  for (std::size_t i = s[0] == '/' ? 1 : 0; plain && i < s.size();) {
    const std::size_t j = std::min(s.find('/', i), s.size());
    const std::string_view e(s.data() + i, j - i);
    plain = !e.empty() && e != "." && e != "..";
    i = j + 1;
  }
  return plain ? fs::path(std::move(s)) : fs::path(s).lexically_normal();
}

class ParamChecker {
 public:
  ParamChecker(FileSystem& fs, const SourceFiles& src, Diagnostics& diags, const ProjectRoot& root)
      : fs_(fs), src_(src), diags_(diags), root_(root) {}

  // Converts `raw` to `spec`'s type; reports and returns nullopt on any problem.
  // `files` receives resolved paths of kPath/kDir parameters (keyed by `spec.name`).
  std::optional<Value> convert(const ParamSpec& spec, const RawNode& raw, const std::string& what,
                               NodeDecl* files) {
    switch (spec.type) {
      case ParamType::kBool: {
        if (!raw.is_scalar()) return wrong(spec, raw, what);
        if (raw.text == "true" || raw.text == "True" || raw.text == "TRUE") return Value(true);
        if (raw.text == "false" || raw.text == "False" || raw.text == "FALSE") return Value(false);
        return wrong(spec, raw, what);
      }
      case ParamType::kInt: {
        auto i = scalar_int(raw);
        if (!i) return wrong(spec, raw, what);
        if (!in_range(spec, static_cast<double>(*i), raw, what)) return std::nullopt;
        if (spec.power_of_two && (*i <= 0 || (*i & (*i - 1)) != 0)) {
          src_.error(diags_, raw.loc,
                     "value out of range: " + what + " must be a power of two, got " + raw.text);
          return std::nullopt;
        }
        return Value(*i);
      }
      case ParamType::kReal: {
        auto d = scalar_real(raw);
        if (!d) return wrong(spec, raw, what);
        if (!in_range(spec, *d, raw, what)) return std::nullopt;
        return Value(*d);
      }
      case ParamType::kString:
        if (!raw.is_scalar()) return wrong(spec, raw, what);
        return Value(raw.text);
      case ParamType::kEnum: {
        if (!raw.is_scalar()) return wrong(spec, raw, what);
        if (std::find(spec.choices.begin(), spec.choices.end(), raw.text) == spec.choices.end()) {
          std::string list;
          for (const auto& c : spec.choices) list += (list.empty() ? "" : ", ") + c;
          src_.error(diags_, raw.loc,
                     what + " must be one of " + list + ", got '" + excerpt(raw.text) + "'" +
                         did_you_mean(raw.text, spec.choices));
          return std::nullopt;
        }
        return Value(raw.text);
      }
      case ParamType::kPath:
      case ParamType::kDir: {
        if (!raw.is_scalar() || raw.text.empty()) return wrong(spec, raw, what);
        // Relative paths are relative to the YAML file that wrote them.
        const fs::path p = joined_normal(raw.loc.file(), raw.text);
        // Stat first (it tells whether p is a link, saving contains() an lstat); a path
        // outside the root is reported as that, whatever the stat found.
        bool not_link = false;
        auto st = fs_.stat_checking_link(p, &not_link);
        if (!root_.contains(p, not_link)) {
          src_.error(diags_, raw.loc, what + ": " + root_.outside_message(p));
          return std::nullopt;
        }
        const bool want_dir = spec.type == ParamType::kDir;
        if (st && st->is_other) {  // a FIFO or device would block or never end
          src_.error(diags_, raw.loc,
                     what + " names '" + excerpt(p.string(), 200) + "', which is not a regular file");
          return std::nullopt;
        }
        if (!st || st->is_dir != want_dir) {
          src_.error(diags_, raw.loc,
                     "missing input: " + what + " names " + (want_dir ? "directory" : "file") + " '" +
                         excerpt(p.string(), 200) + "', which " +
                         (st ? "is not a " + std::string(want_dir ? "directory" : "file")
                             : std::string("does not exist")));
          return std::nullopt;
        }
        if (files) {
          files->files[spec.name] = p;
          files->file_stats[spec.name] = *st;
        }
        return Value(p.string());
      }
      case ParamType::kIntList:
      case ParamType::kRealList:
      case ParamType::kStringList: {
        if (!raw.is_seq()) return wrong(spec, raw, what);
        if ((spec.min_items && raw.items.size() < *spec.min_items) ||
            (spec.max_items && raw.items.size() > *spec.max_items)) {
          src_.error(diags_, raw.loc,
                     what + " must have " + items_text(spec) + ", got " + std::to_string(raw.items.size()));
          return std::nullopt;
        }
        ParamSpec elem = spec;
        elem.type = spec.type == ParamType::kIntList    ? ParamType::kInt
                    : spec.type == ParamType::kRealList ? ParamType::kReal
                                                        : ParamType::kString;
        Value::List out;
        bool ok = true;
        for (std::size_t i = 0; i < raw.items.size(); ++i) {
          auto v = convert(elem, raw.items[i], what + "[" + std::to_string(i) + "]", nullptr);
          if (v)
            out.push_back(std::move(*v));
          else
            ok = false;
        }
        if (!ok) return std::nullopt;
        if (spec.increasing)
          for (std::size_t i = 1; i < out.size(); ++i)
            if (!(out[i].as_real() > out[i - 1].as_real())) {
              src_.error(diags_, raw.items[i].loc,
                         "value out of range: " + what + " must be increasing, but item " +
                             std::to_string(i) + " (" + raw.items[i].text + ") is not greater than item " +
                             std::to_string(i - 1) + " (" + raw.items[i - 1].text + ")");
              return std::nullopt;
            }
        return Value(std::move(out));
      }
      case ParamType::kObject: {
        if (!raw.is_map()) return wrong(spec, raw, what);
        std::vector<std::string> names;
        for (const auto& f : spec.fields) names.push_back(f.name);
        Value::Object out;
        std::set<std::string> given;  // fields present, converted or not (a bad one is not "missing")
        bool ok = true;
        for (const auto& [k, v] : raw.entries) {
          const ParamSpec* f = nullptr;
          for (const auto& field : spec.fields)
            if (field.name == k.text) f = &field;
          if (!f) {
            src_.error(diags_, k.loc,
                       "unknown field '" + excerpt(k.text) + "' in " + what + did_you_mean(k.text, names));
            ok = false;
            continue;
          }
          if (!given.insert(k.text).second) {
            src_.error(diags_, k.loc, "duplicate field '" + k.text + "' in " + what);
            ok = false;
            continue;
          }
          auto cv = convert(*f, v, what + "." + k.text, files);
          if (cv)
            out.emplace(k.text, std::move(*cv));
          else
            ok = false;
        }
        for (const auto& f : spec.fields) {
          if (given.count(f.name)) continue;
          if (f.required()) {
            src_.error(diags_, raw.loc, "missing required field '" + f.name + "' in " + what);
            ok = false;
          } else {
            out.emplace(f.name, f.default_value);
          }
        }
        if (!ok) return std::nullopt;
        return Value(std::move(out));
      }
      case ParamType::kObjectList: {
        if (!raw.is_seq()) return wrong(spec, raw, what);
        if ((spec.min_items && raw.items.size() < *spec.min_items) ||
            (spec.max_items && raw.items.size() > *spec.max_items)) {
          src_.error(diags_, raw.loc,
                     what + " must have " + items_text(spec) + ", got " + std::to_string(raw.items.size()));
          return std::nullopt;
        }
        ParamSpec elem = spec;
        elem.type = ParamType::kObject;
        Value::List out;
        bool ok = true;
        for (std::size_t i = 0; i < raw.items.size(); ++i) {
          auto v = convert(elem, raw.items[i], what + "[" + std::to_string(i) + "]", nullptr);
          if (v)
            out.push_back(std::move(*v));
          else
            ok = false;
        }
        if (!ok) return std::nullopt;
        return Value(std::move(out));
      }
      case ParamType::kMap: {
        if (!raw.is_map()) return wrong(spec, raw, what);
        ParamSpec elem = spec;
        elem.type = ParamType::kReal;
        Value::Object out;
        bool ok = true;
        for (const auto& [k, v] : raw.entries) {
          auto cv = convert(elem, v, what + "." + k.text, nullptr);
          if (!cv)
            ok = false;
          else if (!out.emplace(k.text, std::move(*cv)).second) {
            src_.error(diags_, k.loc, "duplicate key '" + k.text + "' in " + what);
            ok = false;
          }
        }
        if (!ok) return std::nullopt;
        return Value(std::move(out));
      }
    }
    return std::nullopt;
  }

 private:
  static std::optional<std::int64_t> scalar_int(const RawNode& raw) {
    if (!raw.is_scalar() || raw.text.empty()) return std::nullopt;
    std::int64_t v = 0;
    const char* b = raw.text.data();
    const char* e = b + raw.text.size();
    if (*b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e) return std::nullopt;
    return v;
  }

  static std::optional<double> scalar_real(const RawNode& raw) {
    if (!raw.is_scalar() || raw.text.empty()) return std::nullopt;
    double v = 0;
    const char* b = raw.text.data();
    const char* e = b + raw.text.size();
    if (*b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e || !std::isfinite(v)) return std::nullopt;
    return v;
  }

  static std::string items_text(const ParamSpec& s) {
    auto items = [](std::size_t n) { return std::to_string(n) + (n == 1 ? " item" : " items"); };
    if (s.min_items && s.max_items) {
      if (*s.min_items == *s.max_items) return "exactly " + items(*s.min_items);
      return std::to_string(*s.min_items) + " to " + items(*s.max_items);
    }
    if (s.min_items) return "at least " + items(*s.min_items);
    return "at most " + items(*s.max_items);
  }

  bool in_range(const ParamSpec& spec, double v, const RawNode& raw, const std::string& what) {
    if ((spec.min && v < *spec.min) || (spec.max && v > *spec.max)) {
      std::string range;
      if (spec.min && spec.max)
        range = "in [" + format_number(*spec.min) + ", " + format_number(*spec.max) + "]";
      else if (spec.min)
        range = ">= " + format_number(*spec.min);
      else
        range = "<= " + format_number(*spec.max);
      src_.error(diags_, raw.loc,
                 "value out of range: " + what + " must be " + range + ", got " + excerpt(raw.text));
      return false;
    }
    return true;
  }

  static std::string format_number(double d) {
    if (d == std::floor(d) && std::fabs(d) < 1e15) return std::to_string(static_cast<long long>(d));
    return format_real(d);
  }

  std::optional<Value> wrong(const ParamSpec& spec, const RawNode& raw, const std::string& what) {
    const std::string got =
        raw.is_scalar() ? "'" + excerpt(raw.text) + "'" : std::string("a ") + raw.kind_name();
    src_.error(diags_, raw.loc,
               "wrong type: " + what + " expects " + param_type_name(spec.type) + ", got " + got);
    return std::nullopt;
  }

  FileSystem& fs_;
  const SourceFiles& src_;
  Diagnostics& diags_;
  const ProjectRoot& root_;
};

// Recipe names that would clash with what shares the output root (out/cache, CMake's
// out/build, out/npm, out/test-images), and node names that would clash with the out dir's own
// bookkeeping (.sylva/, .<node>.tmp.*): refused, so publishing into out/<recipe>/<node>/ can
// never replace or delete them.
bool reserved_recipe_name(const std::string& n) {
  static const std::set<std::string> kReserved = {"cache", "build", "npm", "test-images", "tmp"};
  return n.front() == '.' || kReserved.count(n) > 0;
}
bool reserved_node_name(const std::string& n) { return n.front() == '.'; }

// ---- the loader ----------------------------------------------------------------------

struct NodeEntry {
  RawNode key;
  RawNode body;
};

struct MatrixVar {
  std::string name;
  std::vector<std::string> values;
  SourceLoc loc;
};

class Loader {
 public:
  Loader(const StageRegistry& reg, FileSystem& fs, Diagnostics& diags, const LoadOptions& options)
      : reg_(reg),
        fs_(fs),
        diags_(diags),
        options_(options),
        yaml_(fs, src_, diags, options.parse_cache_dir,
              YamlLimits{options.limits.file_bytes, options.limits.yaml_nodes, options.limits.include_depth}),
        params_(fs, src_, diags, project_root_) {}

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
    node_loc_.reserve(entries_.size());
    expand_nodes();
    check_defaults();
    if (!diags_.empty()) return std::nullopt;
    recipe_.reindex();
    resolve_needs();
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
        read_matrix(v, global_matrix_);
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

  void read_matrix(const RawNode& v, std::vector<MatrixVar>& out) {
    if (v.is_null()) return;
    if (!v.is_map()) {
      err(v.loc, "'matrix' must be a map of variable name to a list of values");
      return;
    }
    for (const auto& [k, val] : v.entries) {
      if (std::any_of(out.begin(), out.end(),
                      [&key = k](const MatrixVar& m) { return m.name == key.text; })) {
        err(k.loc, "duplicate matrix variable '" + k.text + "'");
        continue;
      }
      if (!val.is_seq() || val.items.empty()) {
        err(val.loc, "matrix variable '" + k.text + "' must be a non-empty list of values");
        continue;
      }
      MatrixVar m{k.text, {}, k.loc};
      for (const auto& item : val.items) {
        if (!item.is_scalar())
          err(item.loc, "matrix values must be scalars");
        else
          m.values.push_back(item.text);
      }
      out.push_back(std::move(m));
    }
  }

  // Pass 3 + 4: expansion and per-node checks.
  void expand_nodes() {
    for (const auto& e : entries_) {
      if (diags_.full()) return;  // enough errors reported; the rest are not looked at
      if (too_many_nodes()) return;
      std::vector<MatrixVar> local_matrix;
      const RawNode* body = &e.body;
      RawNode local;  // the body without its `matrix:` key, when it has one
      // A node-level `matrix:` adds or overrides variables for this node only.
      if (e.body.is_map()) {
        for (std::size_t k = 0; k < e.body.entries.size(); ++k) {
          if (e.body.entries[k].first.text != "matrix") continue;
          local_matrix = global_matrix_;
          std::vector<MatrixVar> vars;
          read_matrix(e.body.entries[k].second, vars);
          for (auto& m : vars) {
            auto g = std::find_if(local_matrix.begin(), local_matrix.end(),
                                  [&](const MatrixVar& x) { return x.name == m.name; });
            if (g != local_matrix.end())
              *g = m;
            else
              local_matrix.push_back(m);
          }
          local = e.body;
          local.entries.erase(local.entries.begin() + static_cast<std::ptrdiff_t>(k));
          body = &local;
          break;
        }
      }
      const std::vector<MatrixVar>& matrix = body == &local ? local_matrix : global_matrix_;
      std::vector<VarRef> name_vars, body_vars;
      const std::size_t errors_before = diags_.size();
      bool dollar = false;
      collect_vars(e.key, name_vars, src_, diags_, &dollar);
      collect_vars(*body, body_vars, src_, diags_, &dollar);
      if (diags_.size() != errors_before) continue;  // malformed ${...}: nothing to expand
      if (!dollar) {  // nothing to substitute: the common case, checked without copying the node
        check_node(e.key, *body);
        continue;
      }
      std::vector<const MatrixVar*> used;  // in matrix declaration order
      bool ok = true;
      for (const auto& ref : name_vars) {
        auto m = std::find_if(matrix.begin(), matrix.end(),
                              [&](const MatrixVar& x) { return x.name == ref.name; });
        if (m == matrix.end()) {
          std::vector<std::string> names;
          for (const auto& x : matrix) names.push_back(x.name);
          err(ref.loc, "unknown variable '${" + ref.name + "}'" + did_you_mean(ref.name, names));
          ok = false;
        }
      }
      for (const auto& m : matrix)
        if (std::any_of(name_vars.begin(), name_vars.end(),
                        [&](const VarRef& r) { return r.name == m.name; }))
          used.push_back(&m);
      for (const auto& ref : body_vars) {
        const bool in_name = std::any_of(name_vars.begin(), name_vars.end(),
                                         [&](const VarRef& r) { return r.name == ref.name; });
        if (in_name) continue;
        const bool known =
            std::any_of(matrix.begin(), matrix.end(), [&](const MatrixVar& x) { return x.name == ref.name; });
        err(ref.loc, known ? "variable '${" + ref.name + "}' is used in node '" + e.key.text +
                                 "' but not in its name, so its expansions would share one name"
                           : "unknown variable '${" + ref.name + "}'");
        ok = false;
      }
      if (!ok) continue;
      // Checked before expanding: a matrix of 10^8 combinations is refused at once.
      std::uint64_t combinations = 1;
      for (const MatrixVar* m : used)
        combinations = std::min<std::uint64_t>(combinations * m->values.size(), options_.limits.matrix + 1);
      // A variable whose every value was refused (reported above) has no values: nothing to expand.
      if (combinations == 0) continue;
      if (combinations > options_.limits.matrix) {
        err(e.key.loc, "node '" + excerpt(e.key.text, 80) + "' expands to more than " +
                           std::to_string(options_.limits.matrix) +
                           " nodes over its matrix; raise the limit with --limit matrix=N");
        continue;
      }
      // Cartesian product, first variable outermost.
      std::vector<std::size_t> idx(used.size(), 0);
      for (;;) {
        if (diags_.full() || too_many_nodes()) return;
        std::map<std::string, std::string> vars;
        for (std::size_t i = 0; i < used.size(); ++i) vars[used[i]->name] = used[i]->values[idx[i]];
        check_node(substitute(e.key, vars), substitute(*body, vars));
        std::size_t i = used.size();
        while (i > 0) {
          --i;
          if (++idx[i] < used[i]->values.size()) break;
          idx[i] = 0;
          if (i == 0) {
            i = used.size() + 1;
            break;
          }
        }
        if (used.empty() || i == used.size() + 1) break;
      }
    }
  }

  // True (once reported) when the recipe has more nodes than options_.limits.nodes.
  bool too_many_nodes() {
    if (node_loc_.size() < options_.limits.nodes) return false;
    if (!nodes_reported_)
      err({recipe_.file.string(), 1, 1}, "the recipe has more than " + std::to_string(options_.limits.nodes) +
                                             " nodes; raise the limit with --limit nodes=N");
    nodes_reported_ = true;
    return true;
  }

  void check_node(const RawNode& key, const RawNode& body) {
    if (!key.is_scalar() || !is_valid_name(key.text)) {
      err(key.loc, "invalid node name '" + excerpt(key.text) +
                       "': use letters, digits, '_', '-' and '.' (no path separators)");
      return;
    }
    if (reserved_node_name(key.text)) {
      err(key.loc, "reserved node name '" + key.text +
                       "': names starting with '.' belong to sylva's bookkeeping in the out dir");
      return;
    }
    if (auto it = node_loc_.find(key.text); it != node_loc_.end()) {
      err(key.loc, "duplicate node '" + key.text + "' (first defined at " + it->second.prefix() + ")");
      return;
    }
    node_loc_.emplace(key.text, key.loc);
    NodeDecl node;
    node.name = key.text;
    node.loc = key.loc;
    if (!body.is_map()) {
      err(body.loc, "node '" + key.text + "' must be a map with 'stage', 'needs' and 'with'");
      return;
    }
    static const std::vector<std::string> kNodeKeys = {"stage", "needs", "with", "matrix", "description"};
    const RawNode* stage = nullptr;
    const RawNode* with = nullptr;
    const RawNode* needs = nullptr;
    for (const auto& [k, v] : body.entries) {
      if (std::find(kNodeKeys.begin(), kNodeKeys.end(), k.text) == kNodeKeys.end()) {
        err(k.loc, "unknown key '" + excerpt(k.text) + "' in node '" + node.name + "'" +
                       did_you_mean(k.text, kNodeKeys));
        continue;
      }
      const RawNode** slot = k.text == "stage"   ? &stage
                             : k.text == "with"  ? &with
                             : k.text == "needs" ? &needs
                                                 : nullptr;
      if (!slot) continue;
      if (*slot)
        err(k.loc, "duplicate key '" + k.text + "' in node '" + node.name + "'");
      else
        *slot = &v;
    }
    if (!stage) {
      err(key.loc, "node '" + node.name + "' has no 'stage'");
      return;
    }
    if (!stage->is_scalar()) {
      err(stage->loc, "'stage' must be one stage name, got a " + std::string(stage->kind_name()) +
                          (stage->is_seq() && stage->items.size() == 1 && stage->items[0].is_scalar()
                               ? " (write 'stage: " + excerpt(stage->items[0].text) + "')"
                               : std::string()));
      return;
    }
    node.stage = reg_.find(stage->text);
    if (!node.stage) {
      err(stage->loc,
          "unknown stage '" + excerpt(stage->text) + "'" + did_you_mean(stage->text, reg_.names()));
      return;
    }
    const StageInfo& info = node.stage->info();
    auto param_names = [&] {
      std::vector<std::string> names;
      for (const auto& p : info.params) names.push_back(p.name);
      return names;
    };
    std::set<std::string> given;
    if (with && !with->is_null()) {
      if (!with->is_map()) {
        err(with->loc, "'with' must be a map of parameter name to value");
      } else {
        for (const auto& [k, v] : with->entries) {
          const ParamSpec* spec = find_param(info, k.text);
          if (!spec) {
            err(k.loc, "unknown parameter '" + excerpt(k.text) + "' for stage '" + info.name + "'" +
                           did_you_mean(k.text, param_names()));
            continue;
          }
          if (!given.insert(k.text).second) {
            err(k.loc, "duplicate parameter '" + k.text + "'");
            continue;
          }
          if (auto val = params_.convert(*spec, v, "parameter '" + k.text + "'", &node))
            node.params.emplace(k.text, std::move(*val));
        }
      }
    }
    for (const auto& spec : info.params) {
      if (given.count(spec.name)) continue;
      if (auto d = defaults_.find(spec.name); d != defaults_.end()) {
        used_defaults_.insert(spec.name);
        if (auto val = params_.convert(spec, d->second.second, "default '" + spec.name + "'", &node))
          node.params.emplace(spec.name, std::move(*val));
      } else if (spec.required()) {
        err(key.loc, "node '" + node.name + "' (stage '" + info.name + "') is missing required parameter '" +
                         spec.name + "'");
      } else {
        node.params.emplace(spec.name, spec.default_value);
      }
    }
    if (info.check && node.params.size() == info.params.size()) {
      for (const ParamProblem& p : info.check(node.params))
        err(problem_loc(p.path, with, key.loc), param_problem_text(p));
    }
    if (needs) needs_raw_.emplace(node.name, *needs);
    if (with) with_raw_.emplace(node.name, *with);
    recipe_.nodes.push_back(std::move(node));
  }

  // Where the recipe spells out the value at `path` (ParamProblem::path): the deepest node of it
  // the node's `with:` (or the recipe's defaults, for a parameter taken from there) holds;
  // `node_loc` for a parameter left at its schema default.
  SourceLoc problem_loc(const std::vector<std::string>& path, const RawNode* with,
                        const SourceLoc& node_loc) const {
    if (path.empty()) return node_loc;
    const RawNode* at = nullptr;
    if (with && with->is_map())
      for (const auto& [k, v] : with->entries)
        if (k.text == path[0]) at = &v;
    if (!at)
      if (auto d = defaults_.find(path[0]); d != defaults_.end()) at = &d->second.second;
    if (!at) return node_loc;
    for (std::size_t i = 1; i < path.size(); ++i) {
      const RawNode* next = nullptr;
      if (at->is_map()) {
        for (const auto& [k, v] : at->entries)
          if (k.text == path[i]) next = &v;
      } else if (at->is_seq() && !path[i].empty() && path[i].size() < 10 &&
                 path[i].find_first_not_of("0123456789") == std::string::npos) {
        const std::size_t index = std::stoul(path[i]);
        if (index < at->items.size()) next = &at->items[index];
      }
      if (!next) break;
      at = next;
    }
    return at->loc;
  }

  static const ParamSpec* find_param(const StageInfo& info, const std::string& name) {
    for (const auto& p : info.params)
      if (p.name == name) return &p;
    return nullptr;
  }

  // A default that no node's stage declares is almost certainly misspelled.
  void check_defaults() {
    std::vector<std::string> all;
    for (const auto* s : reg_.all())
      for (const auto& p : s->info().params) all.push_back(p.name);
    for (const auto& [name, kv] : defaults_) {
      if (used_defaults_.count(name)) continue;
      const bool anywhere = std::find(all.begin(), all.end(), name) != all.end();
      bool declared_by_used_stage = false;
      for (const auto& n : recipe_.nodes)
        if (find_param(n.stage->info(), name)) declared_by_used_stage = true;
      if (!anywhere)
        err(kv.first.loc, "unknown parameter '" + name + "' in defaults" + did_you_mean(name, all));
      else if (!declared_by_used_stage)
        err(kv.first.loc, "default '" + name + "' is not a parameter of any stage this recipe uses");
    }
  }

  // Pass 5: `needs` patterns → node names, then input type/count checks.
  void resolve_needs() {
    std::vector<std::string> names;
    for (const auto& n : recipe_.nodes) names.push_back(n.name);
    for (auto& node : recipe_.nodes) {
      auto it = needs_raw_.find(node.name);
      std::vector<RawNode> patterns;
      SourceLoc where = node.loc;
      if (it != needs_raw_.end()) {
        where = it->second.loc;
        if (it->second.is_scalar())
          patterns.push_back(it->second);
        else if (it->second.is_seq())
          patterns = it->second.items;
        else if (!it->second.is_null())
          err(it->second.loc, "'needs' must be a node name, a pattern or a list of them");
      }
      for (const auto& p : patterns) {
        if (!p.is_scalar()) {
          err(p.loc, "'needs' entries must be node names or patterns");
          continue;
        }
        const bool glob = p.text.find_first_of("*?[") != std::string::npos;
        std::vector<std::string> matches;
        if (!glob) {
          if (p.text != node.name && recipe_.find(p.text)) matches.push_back(p.text);
        } else {
          for (const auto& n : names)
            if (n != node.name && fnmatch(p.text.c_str(), n.c_str(), 0) == 0) matches.push_back(n);
        }
        std::sort(matches.begin(), matches.end());
        if (matches.empty()) {
          if (!glob && p.text == node.name)
            err(p.loc, "dependency cycle: " + node.name + " -> " + node.name);
          else
            err(p.loc, "missing input: " + std::string(glob ? "no node matches '" : "no node named '") +
                           p.text + "'" + (glob ? "" : did_you_mean(p.text, names)));
        }
        for (auto& m : matches)
          if (std::find(node.needs.begin(), node.needs.end(), m) == node.needs.end()) node.needs.push_back(m);
      }
      const InputSpec& in = node.stage->info().inputs;
      const int count = static_cast<int>(node.needs.size());
      if (count < in.min || (in.max >= 0 && count > in.max)) {
        std::string want = in.max < 0         ? "at least " + std::to_string(in.min)
                           : in.min == in.max ? std::to_string(in.min)
                                              : std::to_string(in.min) + " to " + std::to_string(in.max);
        err(where, "node '" + node.name + "' (stage '" + node.stage->info().name + "') needs " + want +
                       " input" + ((in.max < 0 ? in.min : in.max) == 1 ? "" : "s") + ", got " +
                       std::to_string(count));
      }
      std::vector<std::string> types;
      bool types_ok = !(count < in.min || (in.max >= 0 && count > in.max));
      for (const auto& up : node.needs) {
        const NodeDecl* u = recipe_.find(up);
        const std::string& type = u->stage->info().output_type;
        types.push_back(type);
        if (std::find(in.types.begin(), in.types.end(), type) == in.types.end()) {
          types_ok = false;
          std::string accepted;
          for (const auto& t : in.types) accepted += (accepted.empty() ? "" : ", ") + t;
          err(where, "node '" + node.name + "' cannot take '" + up + "' as input: stage '" +
                         node.stage->info().name + "' accepts " +
                         (accepted.empty() ? "no inputs" : accepted) + ", but '" + up + "' makes a " + type);
        }
      }
      const StageInfo& info = node.stage->info();
      if (info.check_inputs && types_ok && node.params.size() == info.params.size()) {
        const auto w = with_raw_.find(node.name);
        for (const ParamProblem& p : info.check_inputs(node.params, types))
          err(problem_loc(p.path, w == with_raw_.end() ? nullptr : &w->second, node.loc),
              param_problem_text(p));
      }
    }
  }

  const StageRegistry& reg_;
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
  std::map<std::string, std::pair<RawNode, RawNode>> defaults_;
  std::set<std::string> used_defaults_;
  std::vector<NodeEntry> entries_;
  std::unordered_map<std::string, SourceLoc> node_loc_;
  std::map<std::string, RawNode> needs_raw_;
  std::map<std::string, RawNode> with_raw_;  // each node's `with:`, for StageInfo::check_inputs
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
