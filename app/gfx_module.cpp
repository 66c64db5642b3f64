// The graphics module's entry point (libsylva_gfx.so; app/gfx_module.h): the heavy stages
// (stages/register_gfx_stages.cpp) and the commands that render (render, verify, lodcheck,
// impostorcheck), with the same global options and parse rules as the binary's command line and
// the binary's CommandContext (the module wires no file system or clock of its own).
#include "app/gfx_module.h"

#include <memory>
#include <vector>

#include "app/impostorcheck_command.h"
#include "app/lodcheck_command.h"
#include "app/render_command.h"
#include "app/verify_command.h"
#include "stages/register_gfx_stages.h"

namespace sylva {

namespace {

const StageRegistry& gfx_stages() {
  static const StageRegistry* registry = [] {
    auto* r = new StageRegistry;  // lives until the process exits (main leaves with _Exit)
    register_gfx_stages(*r);
    return r;
  }();
  return *registry;
}

const Stage* find_stage(const char* name) { return gfx_stages().find(name); }

int run_command(int argc, const char* const* argv, CommandContext& ctx) {
  try {
    CLI::App app{"sylva: a headless batch asset pipeline for trees and forests"};
    app.require_subcommand(1);
    add_global_options(app, ctx.options);
    std::vector<std::unique_ptr<CliCommand>> commands;
    commands.push_back(make_impostorcheck_command());
    commands.push_back(make_lodcheck_command());
    commands.push_back(make_render_command());
    commands.push_back(make_verify_command());
    std::vector<std::pair<CLI::App*, CliCommand*>> subs;
    for (auto& c : commands) subs.emplace_back(c->add_to(app), c.get());
    if (auto code = parse_command_line(app, argc, argv, ctx.io)) return *code;
    for (auto& [sub, cmd] : subs)
      if (sub->parsed()) return cmd->run(ctx);
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(ctx.io.err, "error: %s\n", e.what());
    return kExitBuildFailed;
  }
}

const GfxModule kModule{kGfxModuleAbi, &find_stage, &run_command};

}  // namespace

}  // namespace sylva

extern "C" __attribute__((visibility("default"))) const sylva::GfxModule* sylva_gfx_module() {
  return &sylva::kModule;
}
