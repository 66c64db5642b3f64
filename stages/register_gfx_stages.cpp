#include "stages/register_gfx_stages.h"

#include "stages/forest/forest_stage.h"
#include "stages/impostor/impostor_stage.h"
#include "stages/pack/pack_stage.h"
#include "stages/verify/verify_stage.h"

// Each heavy stage folder exposes its factory in its adapter header and its StageInfo in
// <name>_info.h (registered lazily by register_stages.cpp); list them here, sorted.

namespace sylva {

void register_gfx_stages(StageRegistry& registry) {
  registry.add(make_forest_stage());
  registry.add(make_impostor_stage());
  registry.add(make_pack_stage());
  registry.add(make_verify_stage());
}

}  // namespace sylva
