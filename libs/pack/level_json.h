// One shipped level as JSON: the object of lod.json's `levels[i]` and of manifest.json's
// `species[].levels[i]` (the same keys in both files, one writer). Keys: file, kind,
// impostor_kind (impostor levels only), source_level, epsilon_m, pixel_error_px,
// switch_distance_m, screen_coverage, primitives, triangles, lines, bytes, position_bits,
// position_error_m, position_float, measured (when measured; lod_json.h says what each means).
#pragma once

#include <nlohmann/json.hpp>

#include "libs/pack/lod_json.h"

namespace sylva::pack {

nlohmann::json level_json(const LodLevel& level);

}  // namespace sylva::pack
