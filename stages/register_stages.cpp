#include "stages/register_stages.h"

#include "stages/forest/forest_info.h"
#include "stages/generate/generate_stage.h"
#include "stages/import/import_stage.h"
#include "stages/impostor/impostor_info.h"
#include "stages/lod/lod_info.h"
#include "stages/mesh/mesh_info.h"
#include "stages/pack/pack_info.h"
#include "stages/verify/verify_info.h"

// Each light stage folder exposes one factory in its adapter header; each lazily loaded one its
// StageInfo in <name>_info.h (and its factory in register_gfx_stages.cpp or
// register_geometry_stages.cpp). List them, sorted.

namespace sylva {

void register_builtin_stages(StageRegistry& registry, StageResolver& gfx, StageResolver& geometry) {
  registry.add(make_lazy_stage(forest_stage_info(), gfx));
  registry.add(make_generate_stage());
  registry.add(make_import_stage());
  registry.add(make_lazy_stage(impostor_stage_info(), gfx));
  registry.add(make_lazy_stage(lod_stage_info(), geometry));
  registry.add(make_lazy_stage(mesh_stage_info(), geometry));
  registry.add(make_lazy_stage(pack_stage_info(), gfx));
  registry.add(make_lazy_stage(verify_stage_info(), gfx));
}

}  // namespace sylva
