// Library plus main(): the only place the real stages, the real disk, the real clock and the real
// signals meet. They make the one CommandContext (app/command_context.h) every command runs
// with, the graphics module's included.
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>

#include "app/cli.h"
#include "app/gfx_loader.h"
#include "app/inspect_command.h"
#include "app/pack_command.h"
#include "libs/render/rasteriser_threads.h"
#include "stages/register_stages.h"

namespace {
std::atomic<bool> g_cancel{false};

extern "C" void on_signal(int sig) {
  // First Ctrl-C: stop starting nodes and let running stages stop at their next check. Every
  // write is temp + rename, so even the second Ctrl-C (default action: die) leaves no partial
  // artifact that a later build would trust.
  g_cancel.store(true);
  std::signal(sig, SIG_DFL);
}
}  // namespace

int main(int argc, char** argv) {
  // Before any thread exists and before the graphics module creates a renderer.
  sylva::render::set_default_rasteriser_threads();
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  // Heavy stages and commands live in libsylva_gfx.so, geometry stages in libsylva_geometry.so,
  // each opened only when one of them runs.
  sylva::ModuleLoader gfx = sylva::ModuleLoader::graphics();
  sylva::ModuleLoader geometry = sylva::ModuleLoader::geometry();
  sylva::StageRegistry registry;
  sylva::register_builtin_stages(registry, gfx, geometry);
  sylva::CliIo io;
  io.err_is_terminal = isatty(STDERR_FILENO) && std::getenv("CI") == nullptr;
  io.cancel = &g_cancel;
  sylva::RealFileSystem fsys;
  fsys.set_cancel_flag(&g_cancel);  // Ctrl-C and SIGTERM stop hashing too
  sylva::SteadyClock clock;
  sylva::CommandContext ctx{fsys, clock, registry, io, {}};
  auto inspect = sylva::make_inspect_command();
  auto pack = sylva::make_pack_command();
  auto gfx_commands = sylva::make_gfx_commands(gfx, argc, argv);
  std::vector<sylva::CliCommand*> commands{inspect.get(), pack.get()};
  for (auto& c : gfx_commands) commands.push_back(c.get());
  const int code = sylva::run_cli(argc, argv, ctx, commands);
  // Leave without running static destructors. The shared EGL renderer (stages/verify) lives on a
  // worker thread's context, and Mesa's llvmpipe threads and LLVM's static destructors racing at
  // exit() corrupted the heap now and then ("corrupted size vs. prev_size", exit 134) after
  // successful builds. Everything sylva writes is already fsynced and renamed; only stdio needs
  // flushing.
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(code);
}
