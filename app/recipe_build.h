// What the commands that work on a recipe's built outputs (`sylva verify`, `sylva lodcheck`, `sylva
// impostorcheck`) share: the global options they inherit from `sylva`, and building some targets of a recipe
// with the real cache, a progress printer and Ctrl-C, as `sylva build` does.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/cli.h"
#include "pipeline/executor.h"
#include "pipeline/recipe.h"

namespace sylva {

// The value of a global option (`sylva --out DIR verify ...`) if it was given; `parent` is the
// top-level app the subcommand was added to (may be null).
std::optional<std::string> global_option(const CLI::App* parent, const char* name);

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

// Builds `targets` (and what they need) of `recipe`. On failure prints why to io.err, prefixed
// with `command` ("sylva verify"), and sets exit_code (usage error, build failure, interrupted).
RecipeBuild build_recipe_targets(const Recipe& recipe, const std::vector<std::string>& targets,
                                 const CLI::App* parent, int jobs, const CliIo& io, const char* command);

// The files of a built node as a stage would receive them as input.
InputArtifact input_artifact(const Recipe& recipe, const RecipeBuild& built, const std::string& node);

}  // namespace sylva
