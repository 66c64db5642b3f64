// QSM cylinder table parser. Phases, in the order parse_cylinder_table() runs them:
//   1. find the first significant line (not blank, not a '#' comment) and the separator;
//   2. map columns to roles (from the header, the `columns` option, or TreeQSM's order);
//   3. parse and check every row, keeping only the fields a role uses;
//   4. resolve ids to rows and check the topology (one root, parents exist, no cycles).
#include "stages/import/qsm_table.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <unordered_map>

#include "stages/import/import_error.h"
#include "stages/import/text_scan.h"

namespace sylva::import {

namespace {

using text::NumberStatus;

// ---- 2. column roles -------------------------------------------------------------------

enum Role : int {
  kId,
  kParent,
  kRadius,
  kLength,
  kStartX,
  kStartY,
  kStartZ,
  kEndX,
  kEndY,
  kEndZ,
  kAxisX,
  kAxisY,
  kAxisZ,
  kBranch,
  kOrder,
  kRoleCount
};

struct Alias {
  std::string_view name;  // normalised (normalize_column_name)
  Role role;
};

// Scalar column names. Names not listed are read past (volume, segmentID, mad, ...).
constexpr Alias kScalarAliases[] = {
    {"id", kId},
    {"cylid", kId},
    {"cylinderid", kId},
    {"parent", kParent},
    {"parentid", kParent},
    {"parentcyl", kParent},
    {"parentcylid", kParent},
    {"parentcylinderid", kParent},
    {"radius", kRadius},
    {"radiuscyl", kRadius},
    {"cylradius", kRadius},
    {"rad", kRadius},
    {"length", kLength},
    {"cyllength", kLength},
    {"len", kLength},
    {"startx", kStartX},
    {"starty", kStartY},
    {"startz", kStartZ},
    {"startpointx", kStartX},
    {"startpointy", kStartY},
    {"startpointz", kStartZ},
    {"xstart", kStartX},
    {"ystart", kStartY},
    {"zstart", kStartZ},
    {"endx", kEndX},
    {"endy", kEndY},
    {"endz", kEndZ},
    {"endpointx", kEndX},
    {"endpointy", kEndY},
    {"endpointz", kEndZ},
    {"xend", kEndX},
    {"yend", kEndY},
    {"zend", kEndZ},
    {"axisx", kAxisX},
    {"axisy", kAxisY},
    {"axisz", kAxisZ},
    {"axisdirectionx", kAxisX},
    {"axisdirectiony", kAxisY},
    {"axisdirectionz", kAxisZ},
    {"directionx", kAxisX},
    {"directiony", kAxisY},
    {"directionz", kAxisZ},
    {"branch", kBranch},
    {"branchid", kBranch},
    {"axisid", kBranch},
    {"branchorder", kOrder},
    {"branchingorder", kOrder},
    {"order", kOrder},
};

// Vector column names: one header name for three data columns (TreeQSM's save_model_text
// writes "start_point" and "axis_direction" above 3 columns each).
constexpr Alias kVectorAliases[] = {
    {"start", kStartX}, {"startpoint", kStartX},   {"end", kEndX},        {"endpoint", kEndX},
    {"axis", kAxisX},   {"axisdirection", kAxisX}, {"direction", kAxisX},
};

// TreeQSM's headerless text export; the first 12 columns are the same in every version.
constexpr std::string_view kTreeQsmColumns[] = {"radius",  "length",    "start_x", "start_y",
                                                "start_z", "axis_x",    "axis_y",  "axis_z",
                                                "parent",  "extension", "branch",  "branch_order"};

struct Layout {
  std::array<int, kRoleCount> field{};   // 0-based field of each role, -1 if absent
  std::vector<std::string> field_names;  // display name of every field
  std::size_t field_count = 0;           // fields per row (0: take the first row's count)
  bool use_axis = false;                 // end = start + axis * length
  bool assumed_order = false;            // headerless, no `columns`: TreeQSM's order assumed
  std::string variant;
};

// Where layout problems point: the header line, or the first row for the `columns` option.
struct LayoutContext {
  std::string_view source;
  int line;
  std::string_view what;  // "header" or "columns parameter"
};

[[noreturn]] void fail(std::string_view source, int line, const std::string& message) {
  throw ImportError(source, line, message);
}

bool complete(const Layout& l, Role x) {
  return l.field[x] >= 0 && l.field[x + 1] >= 0 && l.field[x + 2] >= 0;
}

// Checks that a vector role is either absent or complete; names the missing part.
void check_vector(const Layout& l, Role x, std::string_view label, const LayoutContext& ctx) {
  const int present = (l.field[x] >= 0) + (l.field[x + 1] >= 0) + (l.field[x + 2] >= 0);
  if (present == 0 || present == 3) return;
  static constexpr char kAxes[] = {'x', 'y', 'z'};
  std::string have, missing;
  for (int k = 0; k < 3; ++k) {
    std::string& s = l.field[x + k] >= 0 ? have : missing;
    if (!s.empty()) s += ", ";
    s += l.field[x + k] >= 0 ? l.field_names[static_cast<std::size_t>(l.field[x + k])]
                             : std::string(label) + " " + kAxes[k];
  }
  fail(ctx.source, ctx.line, std::string(ctx.what) + " has " + have + " but no " + missing + " column");
}

std::string variant_of(const std::vector<std::string>& names, const Layout& l) {
  bool archi = false, simpleforest = false;
  for (const auto& n : names) {
    if (normalize_column_name(n) == "cylid") archi = true;
    if (n == "ID" || n == "parentID") simpleforest = true;
  }
  if (archi) return "archi";
  if (simpleforest && complete(l, kEndX)) return "simpleforest";
  if (l.field[kId] < 0 && l.use_axis) return "treeqsm";
  return "generic";
}

Layout make_layout(const std::vector<std::string>& names, const LayoutContext& ctx) {
  Layout l;
  l.field.fill(-1);
  int recognised = 0;
  auto assign = [&](Role role, std::size_t field, std::string display) {
    l.field_names.push_back(std::move(display));
    const int prev = l.field[role];
    if (prev >= 0)
      fail(ctx.source, ctx.line,
           std::string(ctx.what) + ": fields " + std::to_string(prev + 1) + " (" +
               l.field_names[static_cast<std::size_t>(prev)] + ") and " + std::to_string(field + 1) + " (" +
               l.field_names.back() + ") name the same column");
    l.field[role] = static_cast<int>(field);
    ++recognised;
  };
  for (const std::string& raw : names) {
    const std::string norm = normalize_column_name(raw);
    const std::size_t field = l.field_names.size();
    const auto vec = std::find_if(std::begin(kVectorAliases), std::end(kVectorAliases),
                                  [&](const Alias& a) { return a.name == norm; });
    if (vec != std::end(kVectorAliases)) {
      static constexpr const char* kAxes[] = {" x", " y", " z"};
      for (int k = 0; k < 3; ++k)
        assign(static_cast<Role>(vec->role + k), field + static_cast<std::size_t>(k), raw + kAxes[k]);
      continue;
    }
    const auto sca = std::find_if(std::begin(kScalarAliases), std::end(kScalarAliases),
                                  [&](const Alias& a) { return a.name == norm; });
    if (sca != std::end(kScalarAliases))
      assign(sca->role, field, raw);
    else
      l.field_names.push_back(raw);
  }
  l.field_count = l.field_names.size();

  if (recognised == 0)
    fail(ctx.source, ctx.line,
         "unknown " + std::string(ctx.what) + ": none of its " + std::to_string(names.size()) +
             " names is a recognised QSM column (such as radius, startX, endX, parentID; "
             "see docs/stages/import.md)");
  check_vector(l, kStartX, "start", ctx);
  check_vector(l, kEndX, "end", ctx);
  check_vector(l, kAxisX, "axis", ctx);
  if (l.field[kRadius] < 0) fail(ctx.source, ctx.line, std::string(ctx.what) + " has no radius column");
  if (!complete(l, kStartX))
    fail(ctx.source, ctx.line,
         std::string(ctx.what) +
             " has no start point columns (startX startY startZ, start_x "
             "start_y start_z, or start_point)");
  if (!complete(l, kEndX)) {
    if (!complete(l, kAxisX) || l.field[kLength] < 0)
      fail(ctx.source, ctx.line,
           std::string(ctx.what) +
               " has neither end point columns (endX endY endZ) nor axis "
               "columns with a length (axis_x axis_y axis_z length)");
    l.use_axis = true;
  }
  if (l.field[kParent] < 0)
    fail(ctx.source, ctx.line,
         std::string(ctx.what) + " has no parent column (parentID, parent or parent_ID)");
  l.variant = variant_of(names, l);
  return l;
}

// Layout of a headerless table whose first row has `fields` fields.
Layout headerless_layout(const TableOptions& opt, std::size_t fields, const LayoutContext& ctx) {
  if (!opt.columns.empty()) {
    Layout l = make_layout(opt.columns, ctx);
    l.variant = "treeqsm_txt";
    return l;
  }
  std::vector<std::string> names(std::begin(kTreeQsmColumns), std::end(kTreeQsmColumns));
  if (fields < names.size())
    fail(ctx.source, ctx.line,
         "truncated row: " + std::to_string(fields) +
             " fields, a headerless TreeQSM table has at "
             "least " +
             std::to_string(names.size()) +
             " (radius length start_x start_y start_z axis_x axis_y axis_z parent extension "
             "branch branch_order)");
  for (std::size_t i = names.size(); i < fields; ++i) names.push_back("column " + std::to_string(i + 1));
  Layout l = make_layout(names, ctx);
  l.variant = "treeqsm_txt";
  l.assumed_order = true;
  return l;
}

bool all_numbers(const std::vector<std::string_view>& fields) {
  double v;
  return std::all_of(fields.begin(), fields.end(),
                     [&](std::string_view f) { return text::parse_real(f, v) == NumberStatus::kOk; });
}
bool no_numbers(const std::vector<std::string_view>& fields) {
  double v;
  return std::none_of(fields.begin(), fields.end(),
                      [&](std::string_view f) { return text::parse_real(f, v) == NumberStatus::kOk; });
}

// "# Branch data" / "# Tree data": the end of the cylinder section in TreeQSM's combined dumps.
bool ends_cylinder_section(std::string_view line) {
  std::string t = normalize_column_name(text::trim(line).substr(1));
  return t.rfind("branchdata", 0) == 0 || t.rfind("treedata", 0) == 0;
}

// ---- 3. rows -----------------------------------------------------------------------------

class RowParser {
 public:
  RowParser(std::string_view source, const Layout& layout) : source_(source), layout_(layout) {}

  Cylinder parse(const std::vector<std::string_view>& fields, int line, std::size_t row) {
    line_ = line;
    fields_ = &fields;
    if (fields.size() != layout_.field_count)
      fail(source_, line,
           (fields.size() < layout_.field_count ? "truncated row: " : "row has ") +
               std::to_string(fields.size()) + " fields, expected " + std::to_string(layout_.field_count));
    Cylinder c;
    c.line = line;
    c.start = vec(kStartX);
    c.radius = real(kRadius);
    if (!(c.radius > 0)) fail_field(kRadius, "radius must be > 0, got " + text::format_real(c.radius));
    if (layout_.use_axis) {
      const double len = real(kLength);
      if (len < 0) fail_field(kLength, "length must be >= 0, got " + text::format_real(len));
      const tree::Vec3 axis = vec(kAxisX);
      const double norm = tree::length(axis);
      if (len > 0 && !(norm > 0)) fail_field(kAxisX, "axis is the zero vector");
      c.end = len > 0 ? c.start + axis * (len / norm) : c.start;
    } else {
      c.end = vec(kEndX);
    }
    c.id = layout_.field[kId] >= 0 ? integer(kId) : static_cast<std::int64_t>(row + 1);
    parent_id_ = integer(kParent);
    if (layout_.field[kBranch] >= 0) c.branch = integer(kBranch);
    if (layout_.field[kOrder] >= 0) {
      c.order = integer(kOrder);
      if (c.order < 0) fail_field(kOrder, "branch order must be >= 0, got " + std::to_string(c.order));
    }
    return c;
  }

  std::int64_t parent_id() const { return parent_id_; }

  [[noreturn]] void fail_field(Role role, const std::string& message) const {
    // TreeQSM versions differ after the first columns (some put added and UnmodRadius before
    // branch and order): when the order was only assumed, say how to give the real one.
    const std::string hint =
        layout_.assumed_order
            ? "; the table has no header, so TreeQSM's column order (" + assumed_order_text() +
                  ") was assumed: if this export orders its columns differently, list them in the "
                  "import stage's `columns` parameter"
            : std::string();
    fail(source_, line_, field_label(layout_, role) + ": " + message + hint);
  }

  static std::string assumed_order_text() {
    std::string t;
    for (std::string_view c : kTreeQsmColumns) t += (t.empty() ? "" : " ") + std::string(c);
    return t;
  }

  static std::string field_label(const Layout& l, Role role) {
    const auto f = static_cast<std::size_t>(l.field[role]);
    return "field " + std::to_string(f + 1) + " (" + l.field_names[f] + ")";
  }

 private:
  std::string_view text_of(Role role) const {
    return (*fields_)[static_cast<std::size_t>(layout_.field[role])];
  }

  void check(NumberStatus st, Role role, const char* expected) const {
    switch (st) {
      case NumberStatus::kOk:
        return;
      case NumberStatus::kEmpty:
        fail_field(role, "empty, expected " + std::string(expected));
      case NumberStatus::kNotFinite:
        fail_field(role, "not a finite number: " + text::quoted(text_of(role)));
      case NumberStatus::kNotNumber:
        fail_field(role, "expected " + std::string(expected) + ", got " + text::quoted(text_of(role)));
    }
  }

  double real(Role role) const {
    double v = 0;
    check(text::parse_real(text_of(role), v), role, "a number");
    return v;
  }

  std::int64_t integer(Role role) const {
    std::int64_t v = 0;
    const NumberStatus st = text::parse_integer(text_of(role), v);
    if (st == NumberStatus::kNotNumber) {
      double r;
      if (text::parse_real(text_of(role), r) == NumberStatus::kOk)
        fail_field(role, "expected an integer, got " + text::quoted(text_of(role)));
    }
    check(st, role, "an integer");
    return v;
  }

  tree::Vec3 vec(Role x) const {
    return {real(x), real(static_cast<Role>(x + 1)), real(static_cast<Role>(x + 2))};
  }

  std::string_view source_;
  const Layout& layout_;
  const std::vector<std::string_view>* fields_ = nullptr;
  int line_ = 0;
  std::int64_t parent_id_ = 0;
};

// ---- 4. topology -------------------------------------------------------------------------

void resolve_topology(CylinderTable& table, const std::vector<std::int64_t>& parent_ids, const Layout& layout,
                      std::string_view source) {
  auto& cyl = table.cylinders;
  const std::size_t n = cyl.size();
  const std::string parent_label = RowParser::field_label(layout, kParent);

  std::unordered_map<std::int64_t, std::int32_t> by_id;
  by_id.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto [it, inserted] = by_id.emplace(cyl[i].id, static_cast<std::int32_t>(i));
    if (!inserted)
      fail(source, cyl[i].line,
           RowParser::field_label(layout, kId) + ": duplicate cylinder id " + std::to_string(cyl[i].id) +
               " (also on line " + std::to_string(cyl[static_cast<std::size_t>(it->second)].line) + ")");
  }
  const bool zero_is_id = by_id.count(0) > 0;

  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t p = parent_ids[i];
    const auto it = by_id.find(p);
    if (it != by_id.end()) {
      if (static_cast<std::size_t>(it->second) == i)
        fail(source, cyl[i].line,
             parent_label + ": cylinder " + std::to_string(cyl[i].id) + " is its own parent");
      cyl[i].parent = it->second;
      continue;
    }
    if (p == -1 || (p == 0 && !zero_is_id)) {
      if (table.root >= 0) {
        const Cylinder& first = cyl[static_cast<std::size_t>(table.root)];
        fail(source, cyl[i].line,
             parent_label + ": cylinder " + std::to_string(cyl[i].id) +
                 " is a second root (the first is cylinder " + std::to_string(first.id) + " on line " +
                 std::to_string(first.line) + "); a table must describe one tree");
      }
      table.root = static_cast<std::int32_t>(i);
      continue;
    }
    fail(source, cyl[i].line,
         parent_label + ": parent " + std::to_string(p) + " is not the id of any cylinder");
  }

  // Every cylinder must reach the root through its parents. Mark the root's descendants via
  // child lists (CSR); any cylinder left unmarked climbs into a cycle.
  std::vector<std::int32_t> first_child(n + 1, 0), children(n);
  for (const Cylinder& c : cyl)
    if (c.parent >= 0) ++first_child[static_cast<std::size_t>(c.parent) + 1];
  for (std::size_t i = 0; i < n; ++i) first_child[i + 1] += first_child[i];
  {
    std::vector<std::int32_t> fill(first_child.begin(), first_child.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      if (cyl[i].parent >= 0)
        children[static_cast<std::size_t>(fill[static_cast<std::size_t>(cyl[i].parent)]++)] =
            static_cast<std::int32_t>(i);
  }
  std::vector<char> reached(n, 0);
  std::vector<std::int32_t> stack;
  if (table.root >= 0) {
    stack.push_back(table.root);
    reached[static_cast<std::size_t>(table.root)] = 1;
  }
  while (!stack.empty()) {
    const auto c = static_cast<std::size_t>(stack.back());
    stack.pop_back();
    for (auto k = first_child[c]; k < first_child[c + 1]; ++k) {
      const auto ch = static_cast<std::size_t>(children[static_cast<std::size_t>(k)]);
      if (!reached[ch]) {
        reached[ch] = 1;
        stack.push_back(static_cast<std::int32_t>(ch));
      }
    }
  }
  const auto unreached = std::find(reached.begin(), reached.end(), 0);
  if (unreached == reached.end()) return;

  // Climb from the first unreached cylinder until a cylinder repeats: that one is on a cycle.
  std::vector<char> seen(n, 0);
  auto c = static_cast<std::int32_t>(unreached - reached.begin());
  while (!seen[static_cast<std::size_t>(c)]) {
    seen[static_cast<std::size_t>(c)] = 1;
    c = cyl[static_cast<std::size_t>(c)].parent;
  }
  std::vector<std::int32_t> cycle{c};
  for (auto p = cyl[static_cast<std::size_t>(c)].parent; p != c; p = cyl[static_cast<std::size_t>(p)].parent)
    cycle.push_back(p);
  // Report at the cycle member that comes first in the file, walking from it.
  const auto first = std::min_element(cycle.begin(), cycle.end());
  std::rotate(cycle.begin(), first, cycle.end());
  std::string path;
  for (const auto m : cycle) path += std::to_string(cyl[static_cast<std::size_t>(m)].id) + " -> ";
  path += std::to_string(cyl[static_cast<std::size_t>(cycle.front())].id);
  const Cylinder& at = cyl[static_cast<std::size_t>(cycle.front())];
  fail(source, at.line,
       parent_label + ": cylinder " + std::to_string(at.id) + " is in a parent cycle: " + path);
}

}  // namespace

std::string normalize_column_name(std::string_view name) {
  std::string_view s = text::trim(name);
  if (!s.empty() && (s.back() == ')' || s.back() == ']')) {
    const char open = s.back() == ')' ? '(' : '[';
    const std::size_t at = s.rfind(open);
    if (at != std::string_view::npos && at > 0) s = s.substr(0, at);
  }
  std::string out;
  out.reserve(s.size());
  for (const char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    if (std::isalnum(u)) out += static_cast<char>(std::tolower(u));
  }
  return out;
}

CylinderTable parse_cylinder_table(std::string_view text, std::string_view source,
                                   const TableOptions& options) {
  const bool headerless = options.headerless || !options.columns.empty();
  text::LineReader reader(text);
  std::string_view line;
  std::vector<std::string_view> fields;

  // 1. First significant line and separator.
  bool found = false;
  while (reader.next(line))
    if (!text::is_blank_or_comment(line)) {
      found = true;
      break;
    }
  if (!found) fail(source, std::max(1, reader.line_number()), "empty file: no header and no cylinder rows");
  const text::Separator sep = text::detect_separator(line);
  text::split_fields(line, sep, fields);

  // 2. Column layout.
  CylinderTable table;
  Layout layout;
  bool pending_row = false;  // the first significant line is data (headerless)
  if (headerless) {
    if (no_numbers(fields))
      fail(source, reader.line_number(),
           "this line looks like a header, but the table was declared headerless (format "
           "treeqsm_txt or the columns parameter); use format qsm to read the header");
    layout = headerless_layout(
        options, fields.size(),
        {source, reader.line_number(), options.columns.empty() ? "header" : "columns parameter"});
    pending_row = true;
  } else {
    if (all_numbers(fields))
      fail(source, reader.line_number(),
           "expected a header line naming the columns, found a row of numbers; for TreeQSM's "
           "headerless text use format treeqsm_txt (and the columns parameter if its column "
           "order differs)");
    std::vector<std::string> names(fields.begin(), fields.end());
    layout = make_layout(names, {source, reader.line_number(), "header"});
  }
  table.variant = layout.variant;
  table.has_branch = layout.field[kBranch] >= 0;
  table.has_order = layout.field[kOrder] >= 0;

  // 3. Rows.
  RowParser rows(source, layout);
  std::vector<std::int64_t> parent_ids;
  const int header_line = reader.line_number();
  while (pending_row || reader.next(line)) {
    if (!pending_row) {
      if (text::is_blank_or_comment(line)) {
        if (headerless && !table.cylinders.empty() && !text::trim(line).empty() &&
            ends_cylinder_section(line))
          break;
        continue;
      }
      text::split_fields(line, sep, fields);
    }
    pending_row = false;
    table.cylinders.push_back(rows.parse(fields, reader.line_number(), table.cylinders.size()));
    parent_ids.push_back(rows.parent_id());
  }
  if (table.cylinders.empty()) fail(source, header_line, "header but no cylinder rows");

  // 4. Topology.
  resolve_topology(table, parent_ids, layout, source);
  return table;
}

}  // namespace sylva::import
