// Registers every stage of the shipped binary (and nothing else): light stages with their
// implementation, the others by their StageInfo alone, resolved when a node of theirs first runs
// (docs/architecture.md, "Heavy libraries load lazily"): through `gfx` (OpenImageIO, EGL/GL) or
// `geometry` (OpenMesh, CGAL, Draco, tinygltf). Generated from stages/CMakeLists.txt's
// sylva_stage() lines.
#pragma once
#include "pipeline/lazy_stage.h"
#include "pipeline/registry.h"

namespace sylva {
void register_builtin_stages(StageRegistry& registry, StageResolver& gfx, StageResolver& geometry);
}
