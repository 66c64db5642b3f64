// The two ways the pack chooses the levels it keeps (docs/stages/pack.md, "Levels kept"), over
// the prepared candidates: the error model's (no meter) and the measured one (a LevelMeter).
// Both return one LevelChoice per candidate, in candidate order.
#pragma once

#include <vector>

#include "stages/pack/candidates.h"
#include "stages/pack/pack_core.h"

namespace sylva::pack {

// Mesh level 0; every further mesh level whose switch distance lies before the impostor's and
// that saves min_saving over the level kept before it; the impostor when it saves min_saving
// over the last kept mesh level.
std::vector<LevelChoice> model_choice(const Prepared& p, const PackOptions& options);

// Per band start, the candidate with the fewest primitives whose shipped file passes the image
// check there (pack_core.h states the order in which candidates are tried). Sets the kept
// candidates of `p` to the grid and scene they ship with (the ones they were measured with).
// Throws what the meter throws.
std::vector<LevelChoice> measured_choice(Prepared& p, const PackOptions& options, LevelMeter& meter);

}  // namespace sylva::pack
