// Recipe values: the typed, canonical form of every stage parameter.
//
// A Value is what a `with:` entry becomes after the recipe loader checked it against the
// stage's ParamSpec: a bool, an integer, a real, a string, a list or an object (string keys,
// kept sorted). Canonical text (canonical()) is what the action key hashes, so two recipes that
// mean the same parameters hash the same whatever their YAML spelling (`1.0` vs `1`, key order).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace sylva {

class Value {
 public:
  using List = std::vector<Value>;
  using Object = std::map<std::string, Value>;  // sorted keys: canonical by construction

  Value() = default;  // null (only for "no default")
  Value(bool b) : v_(b) {}
  Value(std::int64_t i) : v_(i) {}
  Value(int i) : v_(static_cast<std::int64_t>(i)) {}
  Value(double d) : v_(d) {}
  Value(std::string s) : v_(std::move(s)) {}
  Value(const char* s) : v_(std::string(s)) {}
  Value(List l) : v_(std::move(l)) {}
  Value(Object o) : v_(std::move(o)) {}

  bool is_null() const { return std::holds_alternative<std::monostate>(v_); }
  bool is_bool() const { return std::holds_alternative<bool>(v_); }
  bool is_int() const { return std::holds_alternative<std::int64_t>(v_); }
  bool is_real() const { return std::holds_alternative<double>(v_); }
  bool is_string() const { return std::holds_alternative<std::string>(v_); }
  bool is_list() const { return std::holds_alternative<List>(v_); }
  bool is_object() const { return std::holds_alternative<Object>(v_); }

  // Accessors throw std::bad_variant_access on a type mismatch: the loader guarantees types
  // match the ParamSpec, so a mismatch is a programming error in the stage.
  bool as_bool() const { return std::get<bool>(v_); }
  std::int64_t as_int() const { return std::get<std::int64_t>(v_); }
  // Reals accept integers too (YAML `2` for a float parameter is stored as 2.0 anyway).
  double as_real() const { return is_int() ? static_cast<double>(as_int()) : std::get<double>(v_); }
  const std::string& as_string() const { return std::get<std::string>(v_); }
  const List& as_list() const { return std::get<List>(v_); }
  const Object& as_object() const { return std::get<Object>(v_); }

  // Canonical, deterministic JSON text: reals in shortest round-trip form, keys sorted.
  std::string canonical() const;

  friend bool operator==(const Value& a, const Value& b) { return a.v_ == b.v_; }

 private:
  std::variant<std::monostate, bool, std::int64_t, double, std::string, List, Object> v_;
};

// JSON string literal with escapes (shared by canonical() and the CLI's --json output).
std::string json_quote(std::string_view s);
// Shortest text that parses back to exactly `d` (std::to_chars); always contains '.' or 'e'.
std::string format_real(double d);

}  // namespace sylva
