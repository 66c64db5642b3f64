// What stage `import` declares (name, version, parameters, inputs, outputs), apart from its
// implementation: the `sylva` binary registers the stage from this alone and loads the
// implementation (the mesh readers: tinygltf, Draco, Assimp — the geometry module) only when an
// import node runs (docs/architecture.md, "Heavy libraries load lazily").
#pragma once

#include "pipeline/stage.h"

namespace sylva {
StageInfo import_stage_info();
}
