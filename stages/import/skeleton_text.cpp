// Text skeleton reader and writer (format: skeleton_text.h, docs/formats-skeleton.md).
// Reading runs in three phases: collect the lines of each branch (checking every field),
// order the branches parents-first (stable topological sort, cycles reported), then build
// the tree with the attachment defaults and checks.
#include "stages/import/skeleton_text.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <queue>
#include <unordered_map>

#include "stages/import/import_error.h"
#include "stages/import/text_scan.h"
#include "stages/import/value_limits.h"

namespace sylva::import {

namespace {

using text::NumberStatus;

constexpr const char* kFieldNames[] = {"branch", "parent",      "x",        "y",    "z",
                                       "radius", "parent_node", "parent_t", "level"};

struct RawBranch {
  std::int64_t id = 0;
  std::int64_t parent = -1;
  int first_line = 0;
  std::optional<std::int64_t> parent_node, level;
  std::optional<double> parent_t;
  std::vector<tree::Node> nodes;
};

class LineParser {
 public:
  LineParser(std::string_view source, int line, const std::vector<std::string_view>& fields)
      : source_(source), line_(line), fields_(fields) {}

  [[noreturn]] void fail(std::size_t field, const std::string& message) const {
    throw ImportError(source_, line_,
                      "field " + std::to_string(field + 1) + " (" + kFieldNames[field] + "): " + message);
  }

  double real(std::size_t f) const {
    double v = 0;
    check(text::parse_real(fields_[f], v), f, "a number");
    return v;
  }

  std::int64_t integer(std::size_t f, std::int64_t min) const {
    std::int64_t v = 0;
    const NumberStatus st = text::parse_integer(fields_[f], v);
    if (st != NumberStatus::kOk || v < min)
      fail(f, "expected an integer >= " + std::to_string(min) + ", got " + text::quoted(fields_[f]));
    return v;
  }

 private:
  void check(NumberStatus st, std::size_t f, const char* expected) const {
    if (st == NumberStatus::kNotFinite) fail(f, "not a finite number: " + text::quoted(fields_[f]));
    if (st != NumberStatus::kOk)
      fail(f, "expected " + std::string(expected) + ", got " + text::quoted(fields_[f]));
  }

  std::string_view source_;
  int line_;
  const std::vector<std::string_view>& fields_;
};

template <class T>
std::string show(const T& v) {
  if constexpr (std::is_same_v<T, double>)
    return text::format_real(v);
  else
    return std::to_string(v);
}

// One node line's fields, each checked on its own.
struct NodeLine {
  std::int64_t id = 0, parent = -1;
  tree::Node node;
  std::optional<std::int64_t> parent_node, level;
  std::optional<double> parent_t;
};

NodeLine parse_node_line(const LineParser& p, const std::vector<std::string_view>& fields) {
  NodeLine l;
  l.id = p.integer(0, 0);
  l.parent = p.integer(1, -1);
  if (l.parent == l.id) p.fail(1, "branch " + std::to_string(l.id) + " is its own parent");
  l.node = tree::Node{{p.real(2), p.real(3), p.real(4)}, p.real(5)};
  if (l.node.radius < 0) p.fail(5, "radius must be >= 0, got " + text::format_real(l.node.radius));
  if (l.node.radius > kMaxRadiusM)
    p.fail(5, "radius " + text::format_real(l.node.radius) + " m is larger than " +
                  std::to_string(static_cast<long long>(kMaxRadiusM)) + " m");
  for (std::size_t f = 2; f <= 4; ++f)
    if (std::fabs(p.real(f)) > kMaxCoordinateM)
      p.fail(f, "coordinate " + text::format_real(p.real(f)) + " m is farther than " +
                    std::to_string(static_cast<long long>(kMaxCoordinateM)) + " m from the origin");
  if (fields.size() > 6) l.parent_node = p.integer(6, 0);
  if (fields.size() > 7) {
    l.parent_t = p.real(7);
    if (!(*l.parent_t >= 0 && *l.parent_t <= 1))
      p.fail(7, "must be in [0, 1], got " + text::format_real(*l.parent_t));
  }
  if (fields.size() > 8) l.level = p.integer(8, 0);
  if (l.parent < 0 && fields.size() > 6) p.fail(6, "a root branch (parent -1) has no attachment fields");
  return l;
}

// A further line of branch `b`: it must follow the branch's earlier lines, name the same parent
// and repeat attachment fields only with the first line's values.
void check_continuation(const LineParser& p, const NodeLine& l, const RawBranch& b, bool consecutive,
                        std::string_view source, int ln) {
  if (!consecutive)
    throw ImportError(source, ln,
                      "branch " + std::to_string(l.id) +
                          " continues here after other branches; "
                          "a branch's lines must be consecutive (it started on line " +
                          std::to_string(b.first_line) + ")");
  const std::string first = "the branch's first line (line " + std::to_string(b.first_line) + ")";
  if (l.parent != b.parent)
    p.fail(1,
           "parent " + std::to_string(l.parent) + " here but " + std::to_string(b.parent) + " on " + first);
  auto same = [&](std::size_t f, const auto& here, const auto& there) {
    if (!here) return;
    if (!there) p.fail(f, "attachment fields go on " + first);
    if (*here != *there) p.fail(f, show(*here) + " here but " + show(*there) + " on " + first);
  };
  same(6, l.parent_node, b.parent_node);
  same(7, l.parent_t, b.parent_t);
  same(8, l.level, b.level);
}

// The file's branches in order of first appearance, and where each id sits among them.
struct RawSkeleton {
  std::vector<RawBranch> raw;
  std::unordered_map<std::int64_t, std::size_t> by_id;
};

// Phase 1: lines -> raw branches, every field checked.
RawSkeleton read_branches(std::string_view text, std::string_view source) {
  RawSkeleton sk;
  text::LineReader reader(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  std::size_t current = static_cast<std::size_t>(-1);
  while (reader.next(line)) {
    const int ln = reader.line_number();
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    text::split_fields(line, text::Separator::kWhitespace, fields);
    if (fields.empty()) continue;
    if (fields.size() < 6 || fields.size() > 9)
      throw ImportError(source, ln,
                        "expected 6 to 9 fields (branch parent x y z radius [parent_node "
                        "[parent_t [level]]]), got " +
                            std::to_string(fields.size()));
    const LineParser p(source, ln, fields);
    const NodeLine l = parse_node_line(p, fields);
    const auto [it, inserted] = sk.by_id.emplace(l.id, sk.raw.size());
    if (inserted) {
      RawBranch b;
      b.id = l.id;
      b.parent = l.parent;
      b.first_line = ln;
      b.parent_node = l.parent_node;
      b.parent_t = l.parent_t;
      b.level = l.level;
      sk.raw.push_back(std::move(b));
      current = it->second;
    } else {
      check_continuation(p, l, sk.raw[it->second], it->second == current, source, ln);
    }
    sk.raw[current].nodes.push_back(l.node);
  }
  if (sk.raw.empty())
    throw ImportError(source, std::max(1, reader.line_number()), "empty skeleton: no node lines");
  return sk;
}

// Climbs parents from the first branch `order` leaves out until one repeats: it lies on a cycle,
// which is reported from its smallest branch.
[[noreturn]] void throw_parent_cycle(const RawSkeleton& sk, const std::vector<std::size_t>& order,
                                     std::string_view source) {
  const std::vector<RawBranch>& raw = sk.raw;
  const std::size_t n = raw.size();
  std::vector<char> placed(n, 0), seen(n, 0);
  for (const std::size_t i : order) placed[i] = 1;
  std::size_t c = static_cast<std::size_t>(std::find(placed.begin(), placed.end(), 0) - placed.begin());
  while (!seen[c]) {
    seen[c] = 1;
    c = sk.by_id.at(raw[c].parent);
  }
  std::vector<std::size_t> cycle{c};
  for (std::size_t p = sk.by_id.at(raw[c].parent); p != c; p = sk.by_id.at(raw[p].parent)) cycle.push_back(p);
  std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
  std::string path;
  for (const std::size_t m : cycle) path += std::to_string(raw[m].id) + " -> ";
  path += std::to_string(raw[cycle.front()].id);
  throw ImportError(
      source, raw[cycle.front()].first_line,
      "field 2 (parent): branch " + std::to_string(raw[cycle.front()].id) + " is in a parent cycle: " + path);
}

// Phase 2: checks per branch, then a stable parents-first order (Kahn, smallest appearance first).
std::vector<std::size_t> parents_first(const RawSkeleton& sk, std::string_view source) {
  const std::size_t n = sk.raw.size();
  std::vector<std::vector<std::size_t>> kids(n);
  std::vector<int> pending(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const RawBranch& b = sk.raw[i];
    if (b.nodes.size() < 2)
      throw ImportError(source, b.first_line,
                        "branch " + std::to_string(b.id) + " has 1 node; a branch needs at least 2");
    if (b.parent < 0) continue;
    const auto it = sk.by_id.find(b.parent);
    if (it == sk.by_id.end())
      throw ImportError(
          source, b.first_line,
          "field 2 (parent): parent branch " + std::to_string(b.parent) + " is not in this file");
    kids[it->second].push_back(i);
    pending[i] = 1;
  }
  std::priority_queue<std::size_t, std::vector<std::size_t>, std::greater<>> ready;
  for (std::size_t i = 0; i < n; ++i)
    if (!pending[i]) ready.push(i);
  std::vector<std::size_t> order;
  order.reserve(n);
  while (!ready.empty()) {
    const std::size_t i = ready.top();
    ready.pop();
    order.push_back(i);
    for (const std::size_t k : kids[i])
      if (--pending[k] == 0) ready.push(k);
  }
  if (order.size() < n) throw_parent_cycle(sk, order, source);
  return order;
}

// Phase 3 for a child: where it hangs on `parent` (the given fields, else the defaults), checked.
void attach(const RawBranch& r, const tree::Branch& parent, tree::Branch& b, std::string_view source) {
  auto fail = [&](std::size_t f, const std::string& message) {
    throw ImportError(source, r.first_line,
                      "field " + std::to_string(f + 1) + " (" + kFieldNames[f] + "): " + message);
  };
  if (r.parent_node) {
    if (static_cast<std::size_t>(*r.parent_node) >= parent.nodes.size())
      fail(6, "node " + std::to_string(*r.parent_node) + " is out of range (parent branch " +
                  std::to_string(r.parent) + " has " + std::to_string(parent.nodes.size()) + " nodes)");
    b.parent_node = static_cast<std::uint32_t>(*r.parent_node);
  } else {
    double best = 0;
    for (std::size_t k = 0; k < parent.nodes.size(); ++k) {
      const tree::Vec3 d = parent.nodes[k].position - r.nodes.front().position;
      if (k == 0 || tree::dot(d, d) < best) {
        best = tree::dot(d, d);
        b.parent_node = static_cast<std::uint32_t>(k);
      }
    }
  }
  b.parent_t = r.parent_t.value_or(0.0);
  if (b.parent_t != 0 && b.parent_node + 1 >= parent.nodes.size())
    fail(7, "must be 0 at the parent's last node (node " + std::to_string(b.parent_node) + ")");
  const std::int64_t level = r.level.value_or(parent.level + 1);
  if (level != parent.level && level != parent.level + 1)
    fail(8, "level " + std::to_string(level) + " must be the parent's level (" +
                std::to_string(parent.level) + ") or one more");
  b.level = static_cast<std::uint32_t>(level);
}

}  // namespace

tree::Tree parse_skeleton_text(std::string_view text, std::string_view source) {
  // 1. Lines -> raw branches, in order of first appearance.
  RawSkeleton sk = read_branches(text, source);

  // 2. Checks per branch, then a stable parents-first order.
  const std::vector<std::size_t> order = parents_first(sk, source);

  // 3. Build, parents first.
  tree::Tree result;
  result.name = "text skeleton";
  std::vector<std::int32_t> index_of(sk.raw.size(), -1);
  for (const std::size_t i : order) {
    RawBranch& r = sk.raw[i];
    tree::Branch b;
    if (r.parent >= 0) {
      b.parent = index_of[sk.by_id.at(r.parent)];
      attach(r, result.branches[static_cast<std::size_t>(b.parent)], b, source);
    }
    b.nodes = std::move(r.nodes);
    index_of[i] = static_cast<std::int32_t>(result.branches.size());
    result.branches.push_back(std::move(b));
  }
  return result;
}

std::string format_skeleton_text(const tree::Tree& tree) {
  std::string out =
      "# sylva text skeleton (docs/formats-skeleton.md)\n"
      "# branch parent x y z radius [parent_node parent_t level]\n";
  for (std::size_t i = 0; i < tree.branches.size(); ++i) {
    const tree::Branch& b = tree.branches[i];
    for (std::size_t k = 0; k < b.nodes.size(); ++k) {
      const tree::Node& nd = b.nodes[k];
      out += std::to_string(i) + ' ' + std::to_string(b.parent) + ' ' + text::format_real(nd.position.x) +
             ' ' + text::format_real(nd.position.y) + ' ' + text::format_real(nd.position.z) + ' ' +
             text::format_real(nd.radius);
      if (k == 0 && b.parent >= 0)
        out += ' ' + std::to_string(b.parent_node) + ' ' + text::format_real(b.parent_t) + ' ' +
               std::to_string(b.level);
      out += '\n';
    }
  }
  return out;
}

}  // namespace sylva::import
