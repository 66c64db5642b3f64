// Stage `mesh`: tree -> one GLB (or .gltf) with the bark as one connected quad mesh (box joints,
// Catmull–Clark) and the foliage. Parameters and rules: docs/stages/mesh.md.
#pragma once

#include <memory>

#include "pipeline/stage.h"

namespace sylva {

std::unique_ptr<Stage> make_mesh_stage();

}  // namespace sylva
