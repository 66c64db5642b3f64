// dlopen with RTLD_LOCAL: the module's copies of the engine's static libraries stay private to
// it (it is also linked with --exclude-libs), so nothing it defines replaces a symbol of the
// binary. RTLD_NOW: a module that cannot resolve a symbol fails here, with a message, rather than
// in the middle of a node.
#include "app/gfx_loader.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace sylva {

namespace {

std::filesystem::path module_path(const std::string& file, const std::string& env_var) {
  if (const char* env = std::getenv(env_var.c_str()); env && *env) return env;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return (ec ? std::filesystem::path(".") : exe.parent_path()) / file;
}

class GfxCommand final : public CliCommand {
 public:
  GfxCommand(GfxCommandInfo info, GfxLoader& loader, int argc, const char* const* argv)
      : info_(info), loader_(loader), argc_(argc), argv_(argv) {}

  CLI::App* add_to(CLI::App& app) override {
    auto* sub = app.add_subcommand(info_.name, info_.summary);
    // Everything after the command name, --help included, is the module's to parse.
    sub->prefix_command();
    sub->allow_extras();
    sub->set_help_flag();
    return sub;
  }

  int run(CommandContext& ctx) override {
    const GfxModule* m = nullptr;
    try {
      m = &loader_.module();
      if (!m->run_command) throw StageError("the module has no commands");
    } catch (const StageError& e) {
      std::fprintf(ctx.io.err, "error: sylva %s: %s\n", info_.name, e.what());
      return kExitBuildFailed;
    }
    return m->run_command(argc_, argv_, ctx);
  }

 private:
  GfxCommandInfo info_;
  GfxLoader& loader_;
  int argc_;
  const char* const* argv_;
};

}  // namespace

const GfxModule& ModuleLoader::module() {
  std::call_once(once_, [this] {
    const std::filesystem::path path = module_path(file_, env_);
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = ::dlerror();
      error_ = "cannot load the " + what_ + " " + path.string() + ": " + (why ? why : "unknown error");
      return;
    }
    using Entry = const GfxModule* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(handle, symbol_.c_str()));
    const GfxModule* m = entry ? entry() : nullptr;
    if (!m || m->abi != kGfxModuleAbi || !m->find_stage) {
      error_ = "the " + what_ + " " + path.string() + " is from another build of sylva (rebuild it)";
      return;
    }
    module_ = m;  // never closed: its stages and renderer live until the process exits
  });
  if (!module_) throw StageError(error_);
  return *module_;
}

const Stage& ModuleLoader::resolve(std::string_view name) {
  const Stage* s = module().find_stage(std::string(name).c_str());
  if (!s) throw StageError("the " + what_ + " has no stage '" + std::string(name) + "'");
  return *s;
}

std::vector<std::unique_ptr<CliCommand>> make_gfx_commands(GfxLoader& loader, int argc,
                                                           const char* const* argv) {
  std::vector<std::unique_ptr<CliCommand>> out;
  for (const auto& info : kGfxCommands) out.push_back(std::make_unique<GfxCommand>(info, loader, argc, argv));
  return out;
}

}  // namespace sylva
