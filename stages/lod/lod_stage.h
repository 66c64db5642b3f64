// Stage `lod`: tree -> LOD chain (lod.glb with MSFT_lod, lod0.glb.., lod.json).
// Seeds: Zhang et al. 2017 (branches, needles), Remolar et al. FSA/VDF (leaves); parameters in
// docs/stages/lod.md.
#pragma once

#include <memory>

#include "pipeline/stage.h"

namespace sylva {

std::unique_ptr<Stage> make_lod_stage();

}  // namespace sylva
