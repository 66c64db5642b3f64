#include "pipeline/param.h"

#include <cctype>

namespace sylva {

const char* param_type_name(ParamType t) {
  switch (t) {
    case ParamType::kBool:
      return "bool";
    case ParamType::kInt:
      return "int";
    case ParamType::kReal:
      return "real";
    case ParamType::kString:
      return "string";
    case ParamType::kEnum:
      return "enum";
    case ParamType::kPath:
      return "path";
    case ParamType::kDir:
      return "directory";
    case ParamType::kIntList:
      return "list of int";
    case ParamType::kRealList:
      return "list of real";
    case ParamType::kStringList:
      return "list of string";
    case ParamType::kObject:
      return "object";
    case ParamType::kMap:
      return "map of real";
    case ParamType::kObjectList:
      return "list of object";
  }
  return "?";
}

namespace {
ParamSpec make(std::string name, ParamType type, Value def) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = type;
  s.default_value = std::move(def);
  return s;
}
template <class T>
Value opt(const std::optional<T>& v) {
  return v ? Value(*v) : Value();
}
}  // namespace

ParamSpec Param::boolean(std::string name, bool def) { return make(std::move(name), ParamType::kBool, def); }
ParamSpec Param::integer(std::string name, std::optional<std::int64_t> def) {
  return make(std::move(name), ParamType::kInt, opt(def));
}
ParamSpec Param::real(std::string name, std::optional<double> def) {
  return make(std::move(name), ParamType::kReal, opt(def));
}
ParamSpec Param::string(std::string name, std::optional<std::string> def) {
  return make(std::move(name), ParamType::kString, opt(def));
}
ParamSpec Param::choice(std::string name, std::vector<std::string> choices, std::optional<std::string> def) {
  auto s = make(std::move(name), ParamType::kEnum, opt(def));
  s.choices = std::move(choices);
  return s;
}
std::optional<std::filesystem::path> param_folder(const ParamSpec& spec, const std::filesystem::path& file) {
  if (spec.type != ParamType::kPath || spec.folder_for.empty()) return std::nullopt;
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (std::string e : spec.folder_for) {
    for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (e == ext) return file.parent_path();
  }
  return std::nullopt;
}

ParamSpec Param::path(std::string name) { return make(std::move(name), ParamType::kPath, {}); }
ParamSpec Param::dir(std::string name) { return make(std::move(name), ParamType::kDir, {}); }
ParamSpec Param::real_list(std::string name, std::optional<Value::List> def) {
  return make(std::move(name), ParamType::kRealList, opt(def));
}
ParamSpec Param::int_list(std::string name, std::optional<Value::List> def) {
  return make(std::move(name), ParamType::kIntList, opt(def));
}
ParamSpec Param::string_list(std::string name, std::optional<Value::List> def) {
  return make(std::move(name), ParamType::kStringList, opt(def));
}
ParamSpec Param::object(std::string name, std::vector<ParamSpec> fields) {
  // An object's default is the object of its fields' defaults; it is required only if a field is.
  Value::Object def;
  bool complete = true;
  for (const auto& f : fields) {
    if (f.required())
      complete = false;
    else
      def.emplace(f.name, f.default_value);
  }
  auto s = make(std::move(name), ParamType::kObject, complete ? Value(std::move(def)) : Value());
  s.fields = std::move(fields);
  return s;
}
ParamSpec Param::object_list(std::string name, std::vector<ParamSpec> fields) {
  auto s = make(std::move(name), ParamType::kObjectList, Value(Value::List{}));
  s.fields = std::move(fields);
  return s;
}
ParamSpec Param::real_map(std::string name, std::optional<Value::Object> def) {
  return make(std::move(name), ParamType::kMap, opt(def));
}

}  // namespace sylva
