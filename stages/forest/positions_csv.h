// Explicit tree positions from a CSV file (docs/stages/forest.md, `positions`): the user's own
// trees, placed before rows and the random fill (layout.h). Pure: text in, trees out.
#pragma once

#include <string>
#include <vector>

#include "stages/forest/layout.h"

namespace sylva::forest {

// Parses explicit positions: CSV with a header naming the columns `species`, `x`, `z` and
// optionally `yaw_deg` and `scale` (any order); species by name among `names`. Blank lines and
// lines starting with '#' are skipped; a UTF-8 byte order mark is ignored. yaw_deg is wrapped to
// [0, 360); scale must lie in 0.001..1000. Throws std::invalid_argument("<source>:<line>: <what>")
// (no line for a file without a header).
std::vector<ExplicitTree> parse_positions_csv(const std::string& text, const std::vector<std::string>& names,
                                              const std::string& source);

}  // namespace sylva::forest
