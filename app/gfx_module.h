// The narrow interface between the `sylva` binary and its graphics module, libsylva_gfx.so:
// the one place heavy libraries (OpenImageIO and its 258 shared libraries, EGL/OpenGL) are
// linked. The binary opens the module with dlopen the first time a stage or command needs it
// (app/gfx_loader.h), so `--help`, `stages`, `graph`, `explain` and a no-op build never load
// them. docs/architecture.md, "Heavy libraries load lazily", says how to add a stage or command.
//
// The module exports one C symbol, sylva_gfx_module(), returning a table of plain functions.
// Binary and module are built together from one tree (same compiler, same headers), so C++
// types cross the boundary; kGfxModuleAbi still guards against a stale module on disk.
#pragma once

#include <string_view>

#include "app/cli.h"
#include "pipeline/registry.h"
#include "pipeline/stage.h"

namespace sylva {

// Bump when GfxModule or the types it passes change shape.
inline constexpr int kGfxModuleAbi = 2;

// The table is shared by the geometry module (app/geometry_module.cpp: OpenMesh, CGAL, Draco,
// tinygltf), which has stages only (run_command is null).
struct GfxModule {
  int abi = kGfxModuleAbi;
  // The implementation of a heavy stage (one the binary registers with make_lazy_stage), or
  // nullptr if the module has no stage of that name. The module owns it for the process's life.
  const Stage* (*find_stage)(const char* name) = nullptr;
  // Runs a heavy command: argv is the whole command line (`sylva [--out D] render ...`); `ctx`
  // is the binary's (app/command_context.h: its file system, clock, stdio, cancel flag and
  // stages), whose options the module parses the global options into again. Returns the exit
  // code.
  int (*run_command)(int argc, const char* const* argv, CommandContext& ctx) = nullptr;
};

// The commands the module runs, with the one-line summary `sylva --help` prints without loading
// it. The module's own command definitions take their summaries from here.
struct GfxCommandInfo {
  const char* name;
  const char* summary;
};
inline constexpr GfxCommandInfo kGfxCommands[] = {
    {"impostorcheck",
     "render each impostor at its switch distance against the full-detail tree from views between its "
     "frames"},
    {"lodcheck",
     "render each LOD level at its switch distance against the full-detail tree and report the image error"},
    {"render", "render a .glb/.gltf file from the views of a camera set to PNG"},
    {"verify", "build a recipe's verify nodes' inputs, compare renderings with references, report"},
};

// The summary of gfx command `name` (for the module's own CLI definitions); "" if unknown.
constexpr const char* gfx_command_summary(std::string_view name) {
  for (const auto& c : kGfxCommands)
    if (name == c.name) return c.summary;
  return "";
}

}  // namespace sylva

extern "C" const sylva::GfxModule* sylva_gfx_module();
extern "C" const sylva::GfxModule* sylva_geometry_module();
