// The binary's side of its lazily loaded modules (app/gfx_module.h): the graphics module
// libsylva_gfx.so (OpenImageIO, EGL/GL) and the geometry module libsylva_geometry.so (OpenMesh,
// CGAL, Draco, tinygltf), each opened with dlopen the first time one of its stages runs (or,
// for the graphics module, a heavy command is chosen), never before.
//
// A module is looked for beside the executable (/proc/self/exe), or at its environment variable
// ($SYLVA_GFX_MODULE, $SYLVA_GEOMETRY_MODULE). When it cannot be loaded, every use throws
// StageError with dlerror()'s reason, so a node fails ("cannot load the graphics module ...") or
// a command exits 1; nothing else is affected.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/gfx_module.h"
#include "pipeline/lazy_stage.h"

namespace sylva {

class ModuleLoader final : public StageResolver {
 public:
  // file: e.g. "libsylva_gfx.so"; env: the variable overriding its path; symbol: its entry
  // point; what: how messages name it ("graphics module").
  ModuleLoader(std::string file, std::string env, std::string symbol, std::string what)
      : file_(std::move(file)), env_(std::move(env)), symbol_(std::move(symbol)), what_(std::move(what)) {}
  static ModuleLoader graphics() {
    return {"libsylva_gfx.so", "SYLVA_GFX_MODULE", "sylva_gfx_module", "graphics module"};
  }
  static ModuleLoader geometry() {
    return {"libsylva_geometry.so", "SYLVA_GEOMETRY_MODULE", "sylva_geometry_module", "geometry module"};
  }
  // The module, loaded on the first call (thread-safe). Throws StageError.
  const GfxModule& module();
  const Stage& resolve(std::string_view name) override;
  bool loaded() const { return module_ != nullptr; }

 private:
  std::string file_, env_, symbol_, what_;
  std::once_flag once_;
  const GfxModule* module_ = nullptr;
  std::string error_;
};
using GfxLoader = ModuleLoader;

// One command per entry of kGfxCommands: declared in the binary's command line (name and
// summary only; its options and --help belong to the module), and run by handing the whole
// command line and the binary's CommandContext to the module. argv must outlive the commands.
std::vector<std::unique_ptr<CliCommand>> make_gfx_commands(GfxLoader& loader, int argc,
                                                           const char* const* argv);

}  // namespace sylva
