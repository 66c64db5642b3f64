// Stage `generate`: species preset -> tree (tree.sylt, bark.png, leaves.png).
// Seed: Nystad 2010 (Weber–Penn with natural rules); parameters in docs/stages/generate.md.
#pragma once

#include <memory>

#include "pipeline/stage.h"

namespace sylva {

std::unique_ptr<Stage> make_generate_stage();

}  // namespace sylva
