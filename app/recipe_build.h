// What the commands that work on a recipe's built outputs (`sylva verify`, `sylva lodcheck`, `sylva
// impostorcheck`; app/check_command.h) use to get at them: choosing nodes of a stage, building some
// targets of a recipe with the context's file system, cache, clock and Ctrl-C and a progress
// printer, as `sylva build` does, and the files of a built node.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/cli.h"
#include "pipeline/executor.h"
#include "pipeline/recipe.h"

namespace sylva {

struct RecipeBuild {
  int exit_code = kExitOk;        // kExitOk, or what the command should return
  std::filesystem::path out_dir;  // <out>/<recipe name>
  BuildSummary summary;

  const NodeReport* report(const std::string& node) const;  // nullptr if the node was not built
};

// The nodes of stage `stage` a command works on: those named in `names` (in that order, once
// each), or every node of the stage when `names` is empty. On error prints one line to io.err
// ("no node 'x' of stage 's' in recipe 'r'; did you mean ...", or "recipe ... has no node of
// stage 's'; add one (<doc_page>)") and returns nullopt: a usage error.
std::optional<std::vector<const NodeDecl*>> select_stage_nodes(const Recipe& recipe,
                                                               const std::string& recipe_file,
                                                               const std::string& stage,
                                                               const std::vector<std::string>& names,
                                                               const std::string& doc_page, const CliIo& io);

// Builds `targets` (and what they need) of `recipe` into <ctx.out_root()>/<recipe name>/ with the
// cache at ctx.cache_root(), `jobs` nodes at a time (0: all cores). On failure prints why to
// ctx.io.err, prefixed with `command` ("sylva verify"), and sets exit_code (usage error, build
// failure, interrupted).
RecipeBuild build_recipe_targets(const Recipe& recipe, const std::vector<std::string>& targets, int jobs,
                                 CommandContext& ctx, const char* command);

// The files of a built node as a stage would receive them as input.
InputArtifact input_artifact(const Recipe& recipe, const RecipeBuild& built, const std::string& node);

}  // namespace sylva
