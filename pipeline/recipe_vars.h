// `${var}` references in recipe text (docs/recipes.md, "Matrix"): finding them and replacing
// them with a matrix combination's values. "$$" is a literal "$" (so "$${x}" is the text "${x}").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "pipeline/diagnostic.h"
#include "pipeline/yaml_tree.h"

namespace sylva {

struct VarRef {
  std::string name;  // as written between "${" and "}" (reported when not an identifier)
  SourceLoc loc;     // the scalar that holds the reference
};

// Appends every `${name}` in the scalars of `n` (keys and values, depth first, in file order)
// to `out`. Reports a name that is not [A-Za-z0-9_]+ and an unterminated "${". `*dollar` is set
// when any scalar contains '$' (then substitution can change the text even without a
// reference: "$$" -> "$"); it is left alone otherwise.
void collect_vars(const RawNode& n, std::vector<VarRef>& out, const SourceFiles& src, Diagnostics& diags,
                  bool* dollar);

// A copy of `n` with each `${name}` in its scalars replaced by vars.at(name) and "$$" by "$".
// Every name referenced must be in `vars` and every "${" terminated (collect_vars reported none).
RawNode substitute_vars(const RawNode& n, const std::map<std::string, std::string>& vars);

}  // namespace sylva
