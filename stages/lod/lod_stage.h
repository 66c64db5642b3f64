// Stage `lod`: tree -> LOD chain (lod.gltf with MSFT_lod, lod<i>.gltf + lod<i>.bin, leaves.png, lod.json).
// Seeds: Zhang et al. 2017 (branches, needles), Remolar et al. FSA/VDF (leaves); parameters in
// docs/stages/lod.md.
#pragma once

#include <memory>

#include "pipeline/stage.h"
#include "stages/lod/chain.h"

namespace sylva {

std::unique_ptr<Stage> make_lod_stage();

// The chain options of a lod node's complete (defaults filled) parameters: what the stage runs
// with, for commands that rebuild part of a chain (`sylva lodcheck`). Throws
// std::invalid_argument if a parameter is missing.
lod::ChainOptions chain_options_from_params(const Value::Object& params);

}  // namespace sylva
