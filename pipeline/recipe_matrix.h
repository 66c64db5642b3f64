// The recipe matrix (docs/recipes.md, "Matrix"): variables with lists of values, and the
// expansion of one node entry into one node per combination of the variables its name uses.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/diagnostic.h"
#include "pipeline/recipe_vars.h"
#include "pipeline/yaml_tree.h"

namespace sylva {

struct MatrixVar {
  std::string name;
  std::vector<std::string> values;  // in file order; empty when every value was refused
  SourceLoc loc;                    // the variable's key
};

// Appends the variables of a `matrix:` map to `out`. Null is an empty matrix. Reports a
// non-map, a variable already in `out`, a variable without a non-empty list, a non-scalar value.
void read_matrix(const RawNode& v, std::vector<MatrixVar>& out, const SourceFiles& src, Diagnostics& diags);

// A node body with its own `matrix:` key: the recipe's matrix with the node's variables added
// (or replacing the recipe's of the same name), and the body without that key.
struct NodeMatrix {
  std::vector<MatrixVar> matrix;
  RawNode body;
};
// nullopt when `body` has no `matrix:` key (the node uses the recipe's matrix as it is).
std::optional<NodeMatrix> node_matrix(const RawNode& body, const std::vector<MatrixVar>& recipe_matrix,
                                      const SourceFiles& src, Diagnostics& diags);

// The variables of `matrix` that the node name uses (`name_vars`), in matrix declaration order.
// Reports, and returns nullopt after reporting all of them, a variable the name uses that the
// matrix lacks, and a variable the body uses that the name does not (its expansions would share
// one name). `node_name` is the name as written (with its `${...}`).
std::optional<std::vector<const MatrixVar*>> matrix_vars_used(const std::string& node_name,
                                                              const std::vector<VarRef>& name_vars,
                                                              const std::vector<VarRef>& body_vars,
                                                              const std::vector<MatrixVar>& matrix,
                                                              const SourceFiles& src, Diagnostics& diags);

// The number of combinations of `used`, capped at `cap` + 1 (so a matrix of 10^8 combinations
// is counted, and refused, without overflow). 0 when a variable has no values.
std::uint64_t matrix_combinations(const std::vector<const MatrixVar*>& used, std::uint64_t cap);

// Calls `visit` with each combination of `used` (variable name -> value; the first variable
// outermost), once with an empty map when `used` is empty. Stops, returning false, as soon as
// `visit` returns false; true after the last combination. Every variable must have values.
bool for_each_combination(const std::vector<const MatrixVar*>& used,
                          const std::function<bool(const std::map<std::string, std::string>&)>& visit);

}  // namespace sylva
