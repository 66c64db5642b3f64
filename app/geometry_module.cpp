// The geometry module's entry point (libsylva_geometry.so; app/gfx_module.h): the stages that
// need OpenMesh, CGAL, Draco or tinygltf (stages/register_geometry_stages.cpp). Kept out of the
// binary because loading those libraries cost every `sylva` process ~2 ms of dynamic linking
// (docs/performance.md, "Engine"), more than a whole no-op build of a small recipe.
#include "app/gfx_module.h"
#include "stages/register_geometry_stages.h"

namespace sylva {

namespace {

const Stage* find_stage(const char* name) {
  static const StageRegistry* registry = [] {
    auto* r = new StageRegistry;  // lives until the process exits (main leaves with _Exit)
    register_geometry_stages(*r);
    return r;
  }();
  return registry->find(name);
}

const GfxModule kModule{kGfxModuleAbi, &find_stage, nullptr};

}  // namespace

}  // namespace sylva

extern "C" __attribute__((visibility("default"))) const sylva::GfxModule* sylva_geometry_module() {
  return &sylva::kModule;
}
