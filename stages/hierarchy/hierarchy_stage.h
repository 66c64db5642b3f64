// Stage `hierarchy`: an imported tree (tree.sylt with source geometry and no skeleton) -> the same
// tree with its reconstructed skeleton and leaves (tree.sylt), the textures it names passed on,
// and hierarchy.json. Parameters and rules: docs/stages/hierarchy.md.
#pragma once

#include <memory>

#include "pipeline/stage.h"

namespace sylva {

std::unique_ptr<Stage> make_hierarchy_stage();

}  // namespace sylva
