// Registers the implementations of the geometry stages (those that need OpenMesh, CGAL, Draco
// or tinygltf). Linked only into the geometry module (app/geometry_module.cpp); the binary
// registers the same stages by their StageInfo with make_lazy_stage (stages/register_stages.cpp).
#pragma once
#include "pipeline/registry.h"

namespace sylva {
void register_geometry_stages(StageRegistry& registry);
}
