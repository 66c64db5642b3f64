// The `sylva` command line as a library function, so tests can drive it with their own stages, a
// fake file system and a fake clock (app/command_context.h), and capture what it prints. main.cpp
// wires the real stages and the real process.
//
// Exit codes (docs/architecture.md): 0 success; 1 build failure (a node failed, or a cache or
// output operation failed); 2 usage or recipe error (nothing was built); 130 interrupted.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/command_context.h"
#include "pipeline/recipe.h"

namespace sylva {

// What a long command (lodcheck, impostorcheck, verify, render) does when it stops for Ctrl-C or
// SIGTERM: one line on io.err ("sylva lodcheck: interrupted; ..."), exit code kExitInterrupted.
// It has written no partial output (reports are staged, app/report_dir.h).
int report_interrupted(const CliIo& io, const char* command);

// A subcommand outside the engine (inspect, render, ...), wired by main.cpp so the engine's CLI
// does not depend on the domain libraries. Check commands derive from CheckCommand
// (app/check_command.h).
class CliCommand {
 public:
  virtual ~CliCommand() = default;
  // Adds the subcommand and its options to `app`; returns it.
  virtual CLI::App* add_to(CLI::App& app) = 0;
  // Runs after a successful parse when this subcommand was chosen; returns the exit code.
  // ctx.options holds the parsed global options.
  virtual int run(CommandContext& ctx) = 0;
};

// Loads and checks a recipe through ctx.fs with ctx.registry's stages. On failure prints every
// diagnostic (file:line:col) and the error count to ctx.io.err and returns nullopt; the caller
// exits with kExitUsage. `out_dir` (optional): the output root, whose .sylva-parse/ keeps parsed
// YAML between runs (pipeline/yaml_tree.h). The project root and limits are those of
// ctx.options (--allow-outside-root, --root, --limit).
std::optional<Recipe> load_recipe_or_report(const std::string& file, CommandContext& ctx,
                                            const std::string& out_dir = "");

// Adds --out, --cache, --allow-outside-root, --root and --limit to the top-level `app`, bound to
// `g` (g must outlive the parse). The binary and the graphics module (app/gfx_module.h) both
// build their command line with it, into the same CommandContext::options, so they agree.
void add_global_options(CLI::App& app, GlobalOptions& g);

// Parses argv into `app`. Returns the exit code when parsing already decided the outcome
// (--help printed: 0; a usage error printed to io.err: 2), nullopt when the command should run.
std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv, const CliIo& io);

// Parses argv (global options into ctx.options) and runs the chosen command, an engine one or
// one of `extra`, with `ctx`.
int run_cli(int argc, const char* const* argv, CommandContext& ctx,
            const std::vector<CliCommand*>& extra = {});

}  // namespace sylva
