// What stage `mesh` declares (name, version, parameters, inputs, outputs), apart from its
// implementation: the `sylva` binary registers the stage from this alone and loads the
// implementation (OpenMesh, CGAL, Draco: the geometry module) only when a mesh node runs
// (docs/architecture.md, "Heavy libraries load lazily").
#pragma once

#include "pipeline/stage.h"

namespace sylva {
StageInfo mesh_stage_info();
}
