#include "pipeline/yaml_tree.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstring>
#include <string_view>

#include "pipeline/digest.h"

namespace sylva {

RawNode::RawNode() = default;

const char* RawNode::kind_name() const {
  switch (kind) {
    case Kind::kNull:
      return "null";
    case Kind::kScalar:
      return "scalar";
    case Kind::kSeq:
      return "list";
    case Kind::kMap:
      return "map";
  }
  return "?";
}

void SourceFiles::add(const std::string& file, std::string text) { texts_[file] = std::move(text); }

std::string SourceFiles::line(const std::string& file, int line) const {
  // Split on demand: a 10,000-node recipe is read on every build, and only errors show lines.
  auto it = texts_.find(file);
  if (it == texts_.end() || line < 1) return {};
  const std::string& t = it->second;
  std::size_t at = 0;
  for (int i = 1; i < line; ++i) {
    at = t.find('\n', at);
    if (at == std::string::npos) return {};
    ++at;
  }
  if (at >= t.size()) return {};
  std::size_t end = t.find('\n', at);
  std::string l = t.substr(at, end == std::string::npos ? std::string::npos : end - at);
  if (!l.empty() && l.back() == '\r') l.pop_back();
  return l;
}

void SourceFiles::error(Diagnostics& diags, const SourceLoc& loc, std::string message) const {
  diags.error(loc, std::move(message), line(loc.file(), loc.line));
}

namespace {

SourceLoc loc_of(const std::shared_ptr<const std::string>& file, const YAML::Mark& m) {
  if (m.line < 0) return {file, 0, 0};
  return {file, m.line + 1, m.column + 1};
}

}  // namespace

namespace {

// The parse cache's entry format: magic, SHA-256 of the source text, then the tree, each node
// as kind, include flag, line, column, text and children (a map's entries as key, value pairs).
constexpr std::string_view kParseMagic = "sylva-parse-v1\n";

void put_u32(std::string& out, std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); }

void put_tree(std::string& out, const RawNode& n) {
  out += static_cast<char>(n.kind);
  out += static_cast<char>(n.include ? 1 : 0);
  put_u32(out, static_cast<std::uint32_t>(n.loc.line));
  put_u32(out, static_cast<std::uint32_t>(n.loc.col));
  put_u32(out, static_cast<std::uint32_t>(n.text.size()));
  out += n.text;
  const std::size_t count = n.is_map() ? n.entries.size() : n.items.size();
  put_u32(out, static_cast<std::uint32_t>(count));
  if (n.is_map()) {
    for (const auto& [k, v] : n.entries) {
      put_tree(out, k);
      put_tree(out, v);
    }
  } else {
    for (const auto& i : n.items) put_tree(out, i);
  }
}

struct TreeReader {
  std::string_view s;
  std::shared_ptr<const std::string> file;
  std::size_t at = 0;
  bool ok = true;
  std::uint32_t u32() {
    if (s.size() - at < 4) {
      ok = false;
      return 0;
    }
    std::uint32_t v;
    std::memcpy(&v, s.data() + at, 4);
    at += 4;
    return v;
  }
  bool node(RawNode& n, int depth) {
    if (depth > kMaxYamlDepth || s.size() - at < 2) return ok = false;
    const int kind = static_cast<unsigned char>(s[at]);
    n.include = s[at + 1] != 0;
    at += 2;
    if (kind > static_cast<int>(RawNode::Kind::kMap)) return ok = false;
    n.kind = static_cast<RawNode::Kind>(kind);
    n.loc = {file, static_cast<int>(u32()), static_cast<int>(u32())};
    const std::uint32_t len = u32();
    if (!ok || s.size() - at < len) return ok = false;
    n.text.assign(s.data() + at, len);
    at += len;
    const std::uint32_t count = u32();
    if (!ok || count > s.size() - at) return ok = false;
    if (n.is_map()) {
      n.entries.resize(count);
      for (auto& [k, v] : n.entries)
        if (!node(k, depth + 1) || !node(v, depth + 1)) return false;
    } else {
      n.items.resize(count);
      for (auto& i : n.items)
        if (!node(i, depth + 1)) return false;
    }
    return ok;
  }
};

// yaml-cpp's tree -> RawNode, bounded. yaml-cpp keeps an alias as a reference to its anchor;
// converting copies it, so counting the converted nodes stops an alias bomb (9 levels of 9
// aliases: 387 million nodes) at the limit. Every later pass over the tree (variables, includes,
// the parse cache) recurses too, so the nesting is bounded once, here, far below what any
// thread's stack holds. `!include` values are marked, and replaced by resolve_includes().
class YamlConverter {
 public:
  YamlConverter(std::shared_ptr<const std::string> file, std::uint64_t max_nodes, const SourceFiles& sources,
                Diagnostics& diags)
      : file_(std::move(file)), max_nodes_(max_nodes), sources_(sources), diags_(diags) {}

  // `n` as a RawNode; a node without a mark of its own is located at `fallback`.
  RawNode convert(const YAML::Node& n, const SourceLoc& fallback) {
    RawNode r;
    if (too_big_ || too_deep_) return r;
    if (++converted_ > max_nodes_) {
      too_big_ = true;
      ok_ = false;
      return r;
    }
    r.loc = n.Mark().line >= 0 ? loc_of(file_, n.Mark()) : fallback;
    if (depth_ >= kMaxYamlDepth) {
      sources_.error(diags_, r.loc, "YAML nested deeper than " + std::to_string(kMaxYamlDepth) + " levels");
      too_deep_ = true;
      ok_ = false;
      return r;
    }
    ++depth_;
    if (n.Tag() == "!include")
      convert_include(n, r);
    else
      convert_value(n, r);
    --depth_;
    return r;
  }

  // False when anything was refused (each reported, except too_big()).
  bool ok() const { return ok_; }
  // More than `max_nodes` nodes: reported by the caller, which names the file.
  bool too_big() const { return too_big_; }

 private:
  void convert_include(const YAML::Node& n, RawNode& r) {
    if (!n.IsScalar()) {
      sources_.error(diags_, r.loc, "!include needs a file name");
      ok_ = false;
      return;
    }
    r.kind = RawNode::Kind::kScalar;
    r.text = n.Scalar();
    r.include = true;
  }

  void convert_value(const YAML::Node& n, RawNode& r) {
    switch (n.Type()) {
      case YAML::NodeType::Scalar:
        r.kind = RawNode::Kind::kScalar;
        r.text = n.Scalar();
        break;
      case YAML::NodeType::Sequence:
        r.kind = RawNode::Kind::kSeq;
        for (const auto& item : n) r.items.push_back(convert(item, r.loc));
        break;
      case YAML::NodeType::Map:
        r.kind = RawNode::Kind::kMap;
        for (auto it = n.begin(); it != n.end(); ++it) {
          RawNode k = convert(it->first, r.loc);
          RawNode v = convert(it->second, k.loc);
          // A null value (`key:`) has no useful mark of its own: point at the key.
          if (v.is_null()) v.loc = k.loc;
          r.entries.emplace_back(std::move(k), std::move(v));
        }
        break;
      default:
        r.kind = RawNode::Kind::kNull;
    }
  }

  std::shared_ptr<const std::string> file_;
  std::uint64_t max_nodes_;
  const SourceFiles& sources_;
  Diagnostics& diags_;
  std::uint64_t converted_ = 0;
  int depth_ = 0;
  bool ok_ = true, too_big_ = false, too_deep_ = false;
};

}  // namespace

std::optional<RawNode> YamlReader::parse(const std::string& name, const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    const SourceLoc at = loc_of(std::make_shared<const std::string>(name), e.mark);
    std::string hint;
    // `{ a: ${x} }` is the most common slip: `{` after `$` is YAML flow syntax.
    if (sources_.line(name, at.line).find("${") != std::string::npos)
      hint = " (inside { } or [ ], quote values that contain ${...})";
    sources_.error(diags_, at, "malformed YAML: " + e.msg + hint);
    return std::nullopt;
  }
  const auto file = std::make_shared<const std::string>(name);
  YamlConverter converter(file, limits_.yaml_nodes, sources_, diags_);
  RawNode out = converter.convert(root, SourceLoc{file, 1, 1});
  if (converter.too_big())
    sources_.error(diags_, SourceLoc{file, 1, 1},
                   "'" + excerpt(name, 200) + "' expands to more than " + std::to_string(limits_.yaml_nodes) +
                       " YAML nodes (aliases count once per use); raise the limit with --limit yaml-nodes=N");
  if (!converter.ok()) return std::nullopt;
  return out;
}

bool YamlReader::resolve_includes(RawNode& n, const std::filesystem::path& file) {
  if (n.include) {
    const std::filesystem::path target = file.parent_path() / n.text;
    if (root_ && !root_->contains(target)) {
      sources_.error(diags_, n.loc, "!include " + root_->outside_message(target.lexically_normal()));
      return false;
    }
    if (stack_.size() >= limits_.include_depth) {
      sources_.error(diags_, n.loc,
                     "!include nested deeper than " + std::to_string(limits_.include_depth) +
                         " files; raise the limit with --limit include-depth=N");
      return false;
    }
    auto inc = read_impl(target, n.loc, /*resolve=*/true);
    if (!inc) return false;
    n = std::move(*inc);
    return true;
  }
  bool ok = true;
  for (auto& i : n.items) ok = resolve_includes(i, file) && ok;
  for (auto& [k, v] : n.entries) ok = resolve_includes(k, file) && resolve_includes(v, file) && ok;
  return ok;
}

std::optional<RawNode> YamlReader::read(const std::filesystem::path& file, const SourceLoc& from) {
  return read_impl(file, from, /*resolve=*/true);
}

std::optional<RawNode> YamlReader::read_unresolved(const std::filesystem::path& file, const SourceLoc& from) {
  return read_impl(file, from, /*resolve=*/false);
}

bool YamlReader::resolve(RawNode& tree, const std::filesystem::path& file) {
  stack_.push_back(file.lexically_normal().string());
  const bool ok = resolve_includes(tree, file);
  stack_.pop_back();
  return ok;
}

std::optional<RawNode> YamlReader::read_impl(const std::filesystem::path& file, const SourceLoc& from,
                                             bool resolve_now) {
  const std::string name = file.lexically_normal().string();
  if (std::find(stack_.begin(), stack_.end(), name) != stack_.end()) {
    std::string chain;
    for (const auto& s : stack_) chain += s + " -> ";
    sources_.error(diags_, from, "include cycle: " + chain + name);
    return std::nullopt;
  }
  std::string why;
  auto text = fs_.read(file, &why, limits_.file_bytes);
  if (!text) {
    if (auto st = fs_.stat(file); st && !st->is_dir && !st->is_other && st->size > limits_.file_bytes)
      why += "; raise the limit with --limit file-bytes=N";
    sources_.error(diags_, from, "cannot read '" + excerpt(name, 200) + "': " + why);
    return std::nullopt;
  }
  sources_.add(name, *text);

  std::optional<RawNode> tree;
  fs::path entry;
  std::string text_hash;
  if (!parse_cache_dir_.empty()) {
    entry = parse_cache_dir_ / sha256_hex(name);
    text_hash = sha256_hex(*text);
    if (auto cached = fs_.read(entry); cached && cached->size() > kParseMagic.size() + 64 &&
                                       cached->compare(0, kParseMagic.size(), kParseMagic) == 0 &&
                                       cached->compare(kParseMagic.size(), 64, text_hash) == 0) {
      TreeReader r{*cached, std::make_shared<const std::string>(name), kParseMagic.size() + 64};
      RawNode n;
      if (r.node(n, 0) && r.at == cached->size()) tree = std::move(n);
    }
  }
  if (!tree) {
    tree = parse(name, *text);
    if (!tree) return std::nullopt;
    if (!entry.empty()) {
      std::string out(kParseMagic);
      out += text_hash;
      put_tree(out, *tree);
      fs_.write_atomic(entry, out, /*durable=*/false);  // best effort: a cache
    }
  }

  if (!resolve_now) return tree;
  stack_.push_back(name);
  const bool ok = resolve_includes(*tree, file);
  stack_.pop_back();
  if (!ok) return std::nullopt;
  return tree;
}

}  // namespace sylva
