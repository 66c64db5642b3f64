// hierarchy.json: what the reconstruction found and what it left out (docs/stages/hierarchy.md,
// "Report").
#pragma once

#include <nlohmann/json.hpp>

#include "libs/tree/source_geometry.h"
#include "stages/hierarchy/reconstruct.h"

namespace sylva::hierarchy {

// The report as JSON; primitive names come from `g`. Deterministic (arrays in part/branch order).
nlohmann::json report_json(const Report& r, const tree::SourceGeometry& g);

}  // namespace sylva::hierarchy
