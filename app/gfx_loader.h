// The binary's side of the graphics module (app/gfx_module.h): opens libsylva_gfx.so with
// dlopen the first time a heavy stage runs or a heavy command is chosen, never before.
//
// The module is looked for beside the executable (/proc/self/exe), or at $SYLVA_GFX_MODULE.
// When it cannot be loaded, every use throws StageError with dlerror()'s reason, so a node
// fails ("cannot load the graphics module ...") or a command exits 1; nothing else is affected.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/gfx_module.h"
#include "pipeline/lazy_stage.h"

namespace sylva {

class GfxLoader final : public StageResolver {
 public:
  // The module, loaded on the first call (thread-safe). Throws StageError.
  const GfxModule& module();
  const Stage& resolve(std::string_view name) override;
  bool loaded() const { return module_ != nullptr; }

 private:
  std::once_flag once_;
  const GfxModule* module_ = nullptr;
  std::string error_;
};

// One command per entry of kGfxCommands: declared in the binary's command line (name and
// summary only; its options and --help belong to the module), and run by handing the whole
// command line to the module. argv must outlive the commands.
std::vector<std::unique_ptr<CliCommand>> make_gfx_commands(GfxLoader& loader, int argc, const char* const* argv,
                                                          const StageRegistry& registry);

}  // namespace sylva
