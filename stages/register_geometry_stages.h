// Registers the implementations of the geometry stages (those that need OpenMesh, CGAL, Draco
// or tinygltf). Linked only into the geometry module (app/geometry_module.cpp); the binary
// registers the same stages by their StageInfo with make_lazy_stage. Both are generated from
// stages/CMakeLists.txt.
#pragma once
#include "pipeline/registry.h"

namespace sylva {
void register_geometry_stages(StageRegistry& registry);
}
