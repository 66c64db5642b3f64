// Stage `forest` (docs/stages/forest.md): species lod artifacts + layout parameters -> a forest
// artifact (instances.json, per-species level files, per-tile instanced glTF, tileset.json,
// cameras.yaml). A heavy stage: registered lazily by its StageInfo (forest_info.h), the
// implementation lives in the graphics module (it reads maps with OpenImageIO).
#pragma once

#include <memory>

#include "pipeline/stage.h"

namespace sylva {

std::unique_ptr<Stage> make_forest_stage();

}  // namespace sylva
