#include "pipeline/yaml_tree.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <sstream>

namespace sylva {

const char* RawNode::kind_name() const {
  switch (kind) {
    case Kind::kNull: return "null";
    case Kind::kScalar: return "scalar";
    case Kind::kSeq: return "list";
    case Kind::kMap: return "map";
  }
  return "?";
}

void SourceFiles::add(const std::string& file, std::string text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    lines.push_back(std::move(l));
  }
  lines_[file] = std::move(lines);
}

std::string SourceFiles::line(const std::string& file, int line) const {
  auto it = lines_.find(file);
  if (it == lines_.end() || line < 1 || line > static_cast<int>(it->second.size())) return {};
  return it->second[line - 1];
}

void SourceFiles::error(Diagnostics& diags, const SourceLoc& loc, std::string message) const {
  diags.error(loc, std::move(message), line(loc.file, loc.line));
}

namespace {

SourceLoc loc_of(const std::string& file, const YAML::Mark& m) {
  if (m.line < 0) return {file, 0, 0};
  return {file, m.line + 1, m.column + 1};
}

}  // namespace

std::optional<RawNode> YamlReader::read(const std::filesystem::path& file, const SourceLoc& from) {
  return read_impl(file, from);
}

std::optional<RawNode> YamlReader::read_impl(const std::filesystem::path& file,
                                             const SourceLoc& from) {
  const std::string name = file.lexically_normal().string();
  if (std::find(stack_.begin(), stack_.end(), name) != stack_.end()) {
    std::string chain;
    for (const auto& s : stack_) chain += s + " -> ";
    sources_.error(diags_, from, "include cycle: " + chain + name);
    return std::nullopt;
  }
  std::string why;
  auto text = fs_.read(file, &why);
  if (!text) {
    sources_.error(diags_, from,
                   "cannot read '" + name + "': " + why);
    return std::nullopt;
  }
  sources_.add(name, *text);

  YAML::Node root;
  try {
    root = YAML::Load(*text);
  } catch (const YAML::Exception& e) {
    const SourceLoc at = loc_of(name, e.mark);
    std::string hint;
    // `{ a: ${x} }` is the most common slip: `{` after `$` is YAML flow syntax.
    if (sources_.line(name, at.line).find("${") != std::string::npos)
      hint = " (inside { } or [ ], quote values that contain ${...})";
    sources_.error(diags_, at, "malformed YAML: " + e.msg + hint);
    return std::nullopt;
  }

  stack_.push_back(name);
  bool ok = true;
  // Converts recursively; `!include` values are replaced by the included file's root.
  auto convert = [&](auto&& self, const YAML::Node& n, const SourceLoc& fallback) -> RawNode {
    RawNode r;
    r.loc = n.Mark().line >= 0 ? loc_of(name, n.Mark()) : fallback;
    if (n.Tag() == "!include") {
      if (!n.IsScalar()) {
        sources_.error(diags_, r.loc, "!include needs a file name");
        ok = false;
        return r;
      }
      const auto target = file.parent_path() / n.Scalar();
      auto inc = read_impl(target, r.loc);
      if (!inc) {
        ok = false;
        return r;
      }
      return *inc;
    }
    switch (n.Type()) {
      case YAML::NodeType::Scalar:
        r.kind = RawNode::Kind::kScalar;
        r.text = n.Scalar();
        break;
      case YAML::NodeType::Sequence:
        r.kind = RawNode::Kind::kSeq;
        for (const auto& item : n) r.items.push_back(self(self, item, r.loc));
        break;
      case YAML::NodeType::Map:
        r.kind = RawNode::Kind::kMap;
        for (auto it = n.begin(); it != n.end(); ++it) {
          RawNode k = self(self, it->first, r.loc);
          RawNode v = self(self, it->second, k.loc);
          // A null value (`key:`) has no useful mark of its own: point at the key.
          if (v.is_null()) v.loc = k.loc;
          r.entries.emplace_back(std::move(k), std::move(v));
        }
        break;
      default:
        r.kind = RawNode::Kind::kNull;
    }
    return r;
  };
  RawNode out = convert(convert, root, SourceLoc{name, 1, 1});
  stack_.pop_back();
  if (!ok) return std::nullopt;
  return out;
}

}  // namespace sylva
