#include "stages/register_geometry_stages.h"

#include "stages/lod/lod_stage.h"
#include "stages/mesh/mesh_stage.h"

// Each geometry stage folder exposes its factory in its adapter header and its StageInfo in
// <name>_info.h (registered lazily by register_stages.cpp); list them here, sorted.

namespace sylva {

void register_geometry_stages(StageRegistry& registry) {
  registry.add(make_lod_stage());
  registry.add(make_mesh_stage());
}

}  // namespace sylva
