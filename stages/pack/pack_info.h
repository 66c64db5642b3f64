// What stage `pack` declares (name, version, parameters, inputs, outputs), apart from its
// implementation: the `sylva` binary registers the stage from this alone and loads the
// implementation (libs/gltf with tinygltf, Draco and meshoptimizer: the geometry module) only
// when a pack node runs (docs/architecture.md, "Heavy libraries load lazily").
#pragma once

#include "pipeline/stage.h"

namespace sylva {
StageInfo pack_stage_info();
}
