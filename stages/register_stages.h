// Registers every real stage of the shipped binary (and nothing else).
#pragma once
#include "pipeline/registry.h"

namespace sylva {
void register_builtin_stages(StageRegistry& registry);
}
