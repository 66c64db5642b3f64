// What stage `lod` declares (name, version, parameters, inputs, outputs), apart from its
// implementation: the `sylva` binary registers the stage from this alone and loads the
// implementation (libs/gltf with Draco and tinygltf: the geometry module) only when a lod node
// runs (docs/architecture.md, "Heavy libraries load lazily").
#pragma once

#include "pipeline/stage.h"

namespace sylva {
StageInfo lod_stage_info();
}
