// One converter per parameter type, each reporting at the most precise location it has: the
// value itself, the list item, or the object's key. Nested values (lists, objects) convert every
// element before failing, so one run reports every bad item.
#include "pipeline/param_checker.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

namespace sylva {
namespace {

namespace fs = std::filesystem;

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

// True if `dir` holds more than `max` regular files, all subdirectories counted; stops at the
// first one past `max`, so a model at the top of a large tree costs a bounded walk.
bool more_files_than(FileSystem& fsys, const fs::path& dir, std::size_t max) {
  std::size_t n = 0;
  std::vector<fs::path> todo{dir};
  while (!todo.empty()) {
    const fs::path d = std::move(todo.back());
    todo.pop_back();
    for (const auto& name : fsys.list(d)) {
      auto st = fsys.stat(d / name);
      if (!st || st->is_other) continue;
      if (st->is_dir)
        todo.push_back(d / name);
      else if (++n > max)
        return true;
    }
  }
  return false;
}

std::optional<std::int64_t> scalar_int(const RawNode& raw) {
  if (!raw.is_scalar() || raw.text.empty()) return std::nullopt;
  std::int64_t v = 0;
  const char* b = raw.text.data();
  const char* e = b + raw.text.size();
  if (*b == '+') ++b;
  auto [p, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || p != e) return std::nullopt;
  return v;
}

std::optional<double> scalar_real(const RawNode& raw) {
  if (!raw.is_scalar() || raw.text.empty()) return std::nullopt;
  double v = 0;
  const char* b = raw.text.data();
  const char* e = b + raw.text.size();
  if (*b == '+') ++b;
  auto [p, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || p != e || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string items_text(const ParamSpec& s) {
  auto items = [](std::size_t n) { return std::to_string(n) + (n == 1 ? " item" : " items"); };
  if (s.min_items && s.max_items) {
    if (*s.min_items == *s.max_items) return "exactly " + items(*s.min_items);
    return std::to_string(*s.min_items) + " to " + items(*s.max_items);
  }
  if (s.min_items) return "at least " + items(*s.min_items);
  return "at most " + items(*s.max_items);
}

std::string format_number(double d) {
  if (d == std::floor(d) && std::fabs(d) < 1e15) return std::to_string(static_cast<long long>(d));
  return format_real(d);
}

}  // namespace

std::optional<Value> ParamChecker::convert(const ParamSpec& spec, const RawNode& raw, const std::string& what,
                                           NodeDecl* files) {
  switch (spec.type) {
    case ParamType::kBool:
      return convert_bool(spec, raw, what);
    case ParamType::kInt:
      return convert_int(spec, raw, what);
    case ParamType::kReal:
      return convert_real(spec, raw, what);
    case ParamType::kString:
      if (!raw.is_scalar()) return wrong(spec, raw, what);
      return Value(raw.text);
    case ParamType::kEnum:
      return convert_enum(spec, raw, what);
    case ParamType::kPath:
    case ParamType::kDir:
      return convert_path(spec, raw, what, files);
    case ParamType::kIntList:
    case ParamType::kRealList:
    case ParamType::kStringList:
      return convert_scalar_list(spec, raw, what);
    case ParamType::kObject:
      return convert_object(spec, raw, what, files);
    case ParamType::kObjectList:
      return convert_object_list(spec, raw, what);
    case ParamType::kMap:
      return convert_map(spec, raw, what);
  }
  return std::nullopt;
}

std::optional<Value> ParamChecker::convert_bool(const ParamSpec& spec, const RawNode& raw,
                                                const std::string& what) {
  if (!raw.is_scalar()) return wrong(spec, raw, what);
  if (raw.text == "true" || raw.text == "True" || raw.text == "TRUE") return Value(true);
  if (raw.text == "false" || raw.text == "False" || raw.text == "FALSE") return Value(false);
  return wrong(spec, raw, what);
}

std::optional<Value> ParamChecker::convert_int(const ParamSpec& spec, const RawNode& raw,
                                               const std::string& what) {
  auto i = scalar_int(raw);
  if (!i) return wrong(spec, raw, what);
  if (!in_range(spec, static_cast<double>(*i), raw, what)) return std::nullopt;
  if (spec.power_of_two && (*i <= 0 || (*i & (*i - 1)) != 0)) {
    src_.error(diags_, raw.loc, "value out of range: " + what + " must be a power of two, got " + raw.text);
    return std::nullopt;
  }
  return Value(*i);
}

std::optional<Value> ParamChecker::convert_real(const ParamSpec& spec, const RawNode& raw,
                                                const std::string& what) {
  auto d = scalar_real(raw);
  if (!d) return wrong(spec, raw, what);
  if (!in_range(spec, *d, raw, what)) return std::nullopt;
  return Value(*d);
}

std::optional<Value> ParamChecker::convert_enum(const ParamSpec& spec, const RawNode& raw,
                                                const std::string& what) {
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

std::optional<Value> ParamChecker::convert_path(const ParamSpec& spec, const RawNode& raw,
                                                const std::string& what, NodeDecl* files) {
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
  // A model file's folder enters the key whole (ParamSpec::with_folder_for); the engine refuses
  // a large one when it computes the key, and this says so first, at the parameter.
  if (auto folder = param_folder(spec, p); folder && more_files_than(fs_, *folder, kMaxFolderFiles)) {
    src_.error(
        diags_, raw.loc,
        what + ": the folder '" + excerpt(folder->string(), 200) + "' of this " + p.extension().string() +
            " file holds more than " + std::to_string(kMaxFolderFiles) +
            " files, and a model's whole folder enters the node's key: give the model a folder of its own");
    return std::nullopt;
  }
  if (files) {
    files->files[spec.name] = p;
    files->file_stats[spec.name] = *st;
  }
  return Value(p.string());
}

std::optional<Value> ParamChecker::convert_scalar_list(const ParamSpec& spec, const RawNode& raw,
                                                       const std::string& what) {
  if (!raw.is_seq()) return wrong(spec, raw, what);
  if (!check_item_count(spec, raw, what)) return std::nullopt;
  ParamSpec elem = spec;
  elem.type = spec.type == ParamType::kIntList    ? ParamType::kInt
              : spec.type == ParamType::kRealList ? ParamType::kReal
                                                  : ParamType::kString;
  auto out = convert_items(elem, raw, what);
  if (!out) return std::nullopt;
  if (spec.increasing)
    for (std::size_t i = 1; i < out->size(); ++i)
      if (!((*out)[i].as_real() > (*out)[i - 1].as_real())) {
        src_.error(diags_, raw.items[i].loc,
                   "value out of range: " + what + " must be increasing, but item " + std::to_string(i) +
                       " (" + raw.items[i].text + ") is not greater than item " + std::to_string(i - 1) +
                       " (" + raw.items[i - 1].text + ")");
        return std::nullopt;
      }
  return Value(std::move(*out));
}

std::optional<Value> ParamChecker::convert_object(const ParamSpec& spec, const RawNode& raw,
                                                  const std::string& what, NodeDecl* files) {
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

std::optional<Value> ParamChecker::convert_object_list(const ParamSpec& spec, const RawNode& raw,
                                                       const std::string& what) {
  if (!raw.is_seq()) return wrong(spec, raw, what);
  if (!check_item_count(spec, raw, what)) return std::nullopt;
  ParamSpec elem = spec;
  elem.type = ParamType::kObject;
  auto out = convert_items(elem, raw, what);
  if (!out) return std::nullopt;
  return Value(std::move(*out));
}

std::optional<Value> ParamChecker::convert_map(const ParamSpec& spec, const RawNode& raw,
                                               const std::string& what) {
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

std::optional<Value::List> ParamChecker::convert_items(const ParamSpec& elem, const RawNode& raw,
                                                       const std::string& what) {
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
  return out;
}

bool ParamChecker::check_item_count(const ParamSpec& spec, const RawNode& raw, const std::string& what) {
  if ((spec.min_items && raw.items.size() < *spec.min_items) ||
      (spec.max_items && raw.items.size() > *spec.max_items)) {
    src_.error(diags_, raw.loc,
               what + " must have " + items_text(spec) + ", got " + std::to_string(raw.items.size()));
    return false;
  }
  return true;
}

bool ParamChecker::in_range(const ParamSpec& spec, double v, const RawNode& raw, const std::string& what) {
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

std::optional<Value> ParamChecker::wrong(const ParamSpec& spec, const RawNode& raw, const std::string& what) {
  const std::string got =
      raw.is_scalar() ? "'" + excerpt(raw.text) + "'" : std::string("a ") + raw.kind_name();
  src_.error(diags_, raw.loc,
             "wrong type: " + what + " expects " + param_type_name(spec.type) + ", got " + got);
  return std::nullopt;
}

}  // namespace sylva
