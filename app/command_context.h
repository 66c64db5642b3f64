// What every `sylva` command is given, and all it may use of the outside world: the file system,
// the clock, stdio with the cancel flag, the stage registry, and the global options of the
// command line being run (--out, --cache, recipe confinement).
//
// app/main.cpp constructs the one real context (RealFileSystem, SteadyClock, stdout/stderr, the
// SIGINT/SIGTERM flag, the real stages); tests construct theirs with fakes
// (tests/support/fake_filesystem.h, tests/support/fake_clock.h). run_cli (app/cli.h) hands it to
// every command, the engine's and the extra ones (CliCommand::run), and the graphics module's
// commands receive the binary's across app/gfx_module.h's table. No command constructs a file
// system or a clock of its own.
#pragma once

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/clock.h"
#include "pipeline/filesystem.h"
#include "pipeline/registry.h"

namespace sylva {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBuildFailed = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInterrupted = 130;

struct CliIo {
  std::FILE* out = stdout;
  std::FILE* err = stderr;
  bool err_is_terminal = false;               // live progress line instead of log lines
  const std::atomic<bool>* cancel = nullptr;  // set by the SIGINT handler
};

// True once Ctrl-C or SIGTERM asked the command to stop.
inline bool cancelled(const CliIo& io) { return io.cancel && io.cancel->load(); }

// The options every subcommand inherits (`sylva --out DIR --cache DIR <command> ...`).
struct GlobalOptions {
  std::string out_dir = "out";
  std::string cache_dir;            // default: $SYLVA_CACHE or <out>/cache
  bool allow_outside_root = false;  // recipes may name any path (trusted recipes only)
  std::string root;                 // bounds every recipe's project root (untrusted recipes)
  std::vector<std::string> limits;  // "name=N" (pipeline/recipe_loader.h, LoadLimits)
};

// The cache directory: `cache_dir` when given (--cache), else $SYLVA_CACHE, else <out_dir>/cache.
std::filesystem::path cache_root_for(const std::string& out_dir, const std::string& cache_dir);

struct CommandContext {
  // Every file a command reads or writes goes through it, the engine's included (Cache, run_build,
  // recipe loading, report directories). Its cancel flag is the one in `io` (hashing stops on it).
  FileSystem& fs;
  const Clock& clock;  // progress lines and timings
  const StageRegistry& registry;
  CliIo io;  // stdout, stderr, whether stderr is a terminal, the cancel flag
  // Filled in when the command line is parsed (add_global_options, app/cli.h): read them in
  // CliCommand::run, not before.
  GlobalOptions options;

  // The output root (--out; default "out"): recipe R's nodes publish into <out root>/R/.
  std::filesystem::path out_root() const { return options.out_dir; }
  // The cache (--cache, else $SYLVA_CACHE, else <out root>/cache).
  std::filesystem::path cache_root() const { return cache_root_for(options.out_dir, options.cache_dir); }
  bool cancelled() const { return sylva::cancelled(io); }
};

}  // namespace sylva
