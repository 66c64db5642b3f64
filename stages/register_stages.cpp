#include "stages/register_stages.h"

#include "stages/generate/generate_stage.h"
#include "stages/import/import_stage.h"
#include "stages/lod/lod_stage.h"
#include "stages/mesh/mesh_stage.h"
#include "stages/verify/verify_stage.h"

// Each stage folder exposes one factory in its adapter header; list them here, sorted.

namespace sylva {

void register_builtin_stages(StageRegistry& registry) {
  registry.add(make_generate_stage());
  registry.add(make_import_stage());
  registry.add(make_lod_stage());
  registry.add(make_mesh_stage());
  registry.add(make_verify_stage());
}

}  // namespace sylva
