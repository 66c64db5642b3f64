#include "stages/register_stages.h"

#include "stages/generate/generate_stage.h"
#include "stages/import/import_stage.h"
#include "stages/lod/lod_stage.h"
#include "stages/mesh/mesh_stage.h"
#include "stages/verify/verify_info.h"

// Each light stage folder exposes one factory in its adapter header; each heavy one its
// StageInfo in <name>_info.h (and its factory in register_gfx_stages.cpp). List them, sorted.

namespace sylva {

void register_builtin_stages(StageRegistry& registry, StageResolver& gfx) {
  registry.add(make_generate_stage());
  registry.add(make_import_stage());
  registry.add(make_lod_stage());
  registry.add(make_mesh_stage());
  registry.add(make_lazy_stage(verify_stage_info(), gfx));
}

}  // namespace sylva
