#include "stages/register_stages.h"

// Each stage folder exposes one factory in its adapter header; list them here, sorted.

namespace sylva {

void register_builtin_stages(StageRegistry& registry) {
  (void)registry;
}

}  // namespace sylva
