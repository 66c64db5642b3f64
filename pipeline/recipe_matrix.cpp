// Expansion is checked before it runs: unknown variables and variables the name does not use
// are reported for the template (once, not per combination), and the combination count is known
// before a single node is made.
#include "pipeline/recipe_matrix.h"

#include <algorithm>

namespace sylva {

void read_matrix(const RawNode& v, std::vector<MatrixVar>& out, const SourceFiles& src, Diagnostics& diags) {
  if (v.is_null()) return;
  if (!v.is_map()) {
    src.error(diags, v.loc, "'matrix' must be a map of variable name to a list of values");
    return;
  }
  for (const auto& [k, val] : v.entries) {
    if (std::any_of(out.begin(), out.end(), [&key = k](const MatrixVar& m) { return m.name == key.text; })) {
      src.error(diags, k.loc, "duplicate matrix variable '" + k.text + "'");
      continue;
    }
    if (!val.is_seq() || val.items.empty()) {
      src.error(diags, val.loc, "matrix variable '" + k.text + "' must be a non-empty list of values");
      continue;
    }
    MatrixVar m{k.text, {}, k.loc};
    for (const auto& item : val.items) {
      if (!item.is_scalar())
        src.error(diags, item.loc, "matrix values must be scalars");
      else
        m.values.push_back(item.text);
    }
    out.push_back(std::move(m));
  }
}

std::optional<NodeMatrix> node_matrix(const RawNode& body, const std::vector<MatrixVar>& recipe_matrix,
                                      const SourceFiles& src, Diagnostics& diags) {
  if (!body.is_map()) return std::nullopt;
  for (std::size_t k = 0; k < body.entries.size(); ++k) {
    if (body.entries[k].first.text != "matrix") continue;
    NodeMatrix out{recipe_matrix, body};
    std::vector<MatrixVar> vars;
    read_matrix(body.entries[k].second, vars, src, diags);
    for (auto& m : vars) {
      auto g = std::find_if(out.matrix.begin(), out.matrix.end(),
                            [&](const MatrixVar& x) { return x.name == m.name; });
      if (g != out.matrix.end())
        *g = m;
      else
        out.matrix.push_back(m);
    }
    out.body.entries.erase(out.body.entries.begin() + static_cast<std::ptrdiff_t>(k));
    return out;
  }
  return std::nullopt;
}

std::optional<std::vector<const MatrixVar*>> matrix_vars_used(const std::string& node_name,
                                                              const std::vector<VarRef>& name_vars,
                                                              const std::vector<VarRef>& body_vars,
                                                              const std::vector<MatrixVar>& matrix,
                                                              const SourceFiles& src, Diagnostics& diags) {
  bool ok = true;
  for (const auto& ref : name_vars) {
    auto m =
        std::find_if(matrix.begin(), matrix.end(), [&](const MatrixVar& x) { return x.name == ref.name; });
    if (m == matrix.end()) {
      std::vector<std::string> names;
      for (const auto& x : matrix) names.push_back(x.name);
      src.error(diags, ref.loc, "unknown variable '${" + ref.name + "}'" + did_you_mean(ref.name, names));
      ok = false;
    }
  }
  std::vector<const MatrixVar*> used;
  for (const auto& m : matrix)
    if (std::any_of(name_vars.begin(), name_vars.end(), [&](const VarRef& r) { return r.name == m.name; }))
      used.push_back(&m);
  for (const auto& ref : body_vars) {
    const bool in_name =
        std::any_of(name_vars.begin(), name_vars.end(), [&](const VarRef& r) { return r.name == ref.name; });
    if (in_name) continue;
    const bool known =
        std::any_of(matrix.begin(), matrix.end(), [&](const MatrixVar& x) { return x.name == ref.name; });
    src.error(diags, ref.loc,
              known ? "variable '${" + ref.name + "}' is used in node '" + node_name +
                          "' but not in its name, so its expansions would share one name"
                    : "unknown variable '${" + ref.name + "}'");
    ok = false;
  }
  if (!ok) return std::nullopt;
  return used;
}

std::uint64_t matrix_combinations(const std::vector<const MatrixVar*>& used, std::uint64_t cap) {
  std::uint64_t combinations = 1;
  for (const MatrixVar* m : used)
    combinations = std::min<std::uint64_t>(combinations * m->values.size(), cap + 1);
  return combinations;
}

bool for_each_combination(const std::vector<const MatrixVar*>& used,
                          const std::function<bool(const std::map<std::string, std::string>&)>& visit) {
  std::vector<std::size_t> idx(used.size(), 0);
  for (;;) {
    std::map<std::string, std::string> vars;
    for (std::size_t i = 0; i < used.size(); ++i) vars[used[i]->name] = used[i]->values[idx[i]];
    if (!visit(vars)) return false;
    // Odometer step: the last variable turns fastest.
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
    if (used.empty() || i == used.size() + 1) return true;
  }
}

}  // namespace sylva
