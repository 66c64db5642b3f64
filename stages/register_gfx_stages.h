// Registers the implementations of the gfx stages (those that need OpenImageIO or EGL/GL).
// Linked only into the graphics module (app/gfx_module.h); the binary registers the same stages
// by their StageInfo with make_lazy_stage. Both are generated from stages/CMakeLists.txt.
#pragma once
#include "pipeline/registry.h"

namespace sylva {
void register_gfx_stages(StageRegistry& registry);
}
