// What stage `forest` declares (name, version, parameters, inputs), without its implementation:
// linked into the `sylva` binary, which loads the implementation from the graphics module when a
// forest node runs (it reads height and density maps with OpenImageIO). docs/stages/forest.md.
#pragma once

#include "pipeline/stage.h"

namespace sylva {

StageInfo forest_stage_info();

// The forest's parameter checks beyond the schema (StageInfo::check): species names (pattern, at
// most 64 characters, not beginning with `tile_`, unique), scale ranges in order, altitude limits
// in order, impostor_parallax rows (pairs, distances increasing, steps integers 0..64), polygon and
// polyline points in x, z pairs, rows naming a listed species, terrain_extent_m's order (and a
// height_map for it to place). `params`:
// the node's complete, typed parameters.
std::vector<ParamProblem> forest_param_problems(const Value::Object& params);

// StageInfo::check_inputs: one `species` entry per lod input (in the order of `needs`).
std::vector<ParamProblem> forest_input_problems(const Value::Object& params,
                                                const std::vector<std::string>& input_types);

}  // namespace sylva
