// Registers every stage of the shipped binary (and nothing else): light stages with their
// implementation, heavy ones (OpenImageIO, EGL/GL) by their StageInfo alone, resolved through
// `gfx` when a node of theirs first runs (docs/architecture.md, "Heavy libraries load lazily").
#pragma once
#include "pipeline/lazy_stage.h"
#include "pipeline/registry.h"

namespace sylva {
void register_builtin_stages(StageRegistry& registry, StageResolver& gfx);
}
