// The `sylva` command line as a library function, so tests can drive it with their own stages
// and capture what it prints. main.cpp wires the real stages and the real process.
//
// Exit codes (docs/architecture.md): 0 success; 1 build failure (a node failed, or a cache or
// output operation failed); 2 usage or recipe error (nothing was built); 130 interrupted.
#pragma once

#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/filesystem.h"
#include "pipeline/recipe.h"
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
// What a long command (lodcheck, impostorcheck, verify, render) does when it stops for Ctrl-C or
// SIGTERM: one line on io.err ("sylva lodcheck: interrupted; ..."), exit code kExitInterrupted.
// It has written no partial output (reports are staged, app/report_dir.h).
int report_interrupted(const CliIo& io, const char* command);

// A subcommand outside the engine (inspect, render, ...), wired by main.cpp so the engine's CLI
// does not depend on the domain libraries.
class CliCommand {
 public:
  virtual ~CliCommand() = default;
  // Adds the subcommand and its options to `app`; returns it.
  virtual CLI::App* add_to(CLI::App& app) = 0;
  // Runs after a successful parse when this subcommand was chosen; returns the exit code.
  virtual int run(const CliIo& io) = 0;
};

// Loads and checks a recipe. On failure prints every diagnostic (file:line:col) and the error
// count to io.err and returns nullopt; the caller exits with kExitUsage. `out_dir` (optional):
// the output root, whose .sylva-parse/ keeps parsed YAML between runs (pipeline/yaml_tree.h).
// The project root and limits are those of the global options (--allow-outside-root, --root,
// --limit) of the command line being run (add_global_options).
std::optional<Recipe> load_recipe_or_report(const std::string& file, const StageRegistry& registry,
                                            FileSystem& fsys, const CliIo& io,
                                            const std::string& out_dir = "");

// The cache directory: `cache_dir` when given (--cache), else $SYLVA_CACHE, else <out_dir>/cache.
std::filesystem::path cache_root_for(const std::string& out_dir, const std::string& cache_dir);

// The options every subcommand inherits (`sylva --out DIR --cache DIR <command> ...`).
struct GlobalOptions {
  std::string out_dir = "out";
  std::string cache_dir;            // default: $SYLVA_CACHE or <out>/cache
  bool allow_outside_root = false;  // recipes may name any path (trusted recipes only)
  std::string root;                 // bounds every recipe's project root (untrusted recipes)
  std::vector<std::string> limits;  // "name=N" (pipeline/recipe_loader.h, LoadLimits)
};
// Adds --out, --cache, --allow-outside-root, --root and --limit to the top-level `app`, bound to
// `g`, which recipe loading then uses (g must outlive the command). The binary and the graphics
// module (app/gfx_module.h) both build their command line with it, so they agree.
void add_global_options(CLI::App& app, GlobalOptions& g);

// Parses argv into `app`. Returns the exit code when parsing already decided the outcome
// (--help printed: 0; a usage error printed to io.err: 2), nullopt when the command should run.
std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv, const CliIo& io);

int run_cli(int argc, const char* const* argv, const StageRegistry& registry, const CliIo& io,
            const std::vector<CliCommand*>& extra = {});

}  // namespace sylva
