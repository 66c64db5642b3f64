// Registers the implementations of the heavy stages (those that need OpenImageIO or EGL/GL).
// Linked only into the graphics module (app/gfx_module.h); the binary registers the same stages
// by their StageInfo with make_lazy_stage (stages/register_stages.cpp).
#pragma once
#include "pipeline/registry.h"

namespace sylva {
void register_gfx_stages(StageRegistry& registry);
}
