// Building part of a recipe for a command: the same file system, cache, progress and exit codes as
// `sylva build`, so `sylva verify` and `sylva lodcheck` never disagree with it about what is built.
#include "app/recipe_build.h"

#include <algorithm>
#include <cstdio>

#include "app/progress.h"
#include "pipeline/cache.h"
#include "pipeline/diagnostic.h"

namespace sylva {

namespace fs = std::filesystem;

const NodeReport* RecipeBuild::report(const std::string& node) const {
  for (const auto& r : summary.nodes)
    if (r.name == node) return &r;
  return nullptr;
}

std::optional<std::vector<const NodeDecl*>> select_stage_nodes(const Recipe& recipe,
                                                               const std::string& recipe_file,
                                                               const std::string& stage,
                                                               const std::vector<std::string>& names,
                                                               const std::string& doc_page, const CliIo& io) {
  std::vector<std::string> of_stage;
  for (const auto& n : recipe.nodes)
    if (n.stage->info().name == stage) of_stage.push_back(n.name);
  std::vector<const NodeDecl*> selected;
  for (const auto& name : names.empty() ? of_stage : names) {
    const NodeDecl* n = recipe.find(name);
    if (!n || n->stage->info().name != stage) {
      std::fprintf(io.err, "error: no node '%s' of stage '%s' in recipe '%s'%s\n", name.c_str(),
                   stage.c_str(), recipe.name.c_str(), did_you_mean(name, of_stage).c_str());
      return std::nullopt;
    }
    if (std::find(selected.begin(), selected.end(), n) == selected.end()) selected.push_back(n);
  }
  if (selected.empty()) {
    std::fprintf(io.err, "error: recipe '%s' (%s) has no node of stage '%s'; add one (%s)\n",
                 recipe.name.c_str(), recipe_file.c_str(), stage.c_str(), doc_page.c_str());
    return std::nullopt;
  }
  return selected;
}

RecipeBuild build_recipe_targets(const Recipe& recipe, const std::vector<std::string>& targets, int jobs,
                                 CommandContext& ctx, const char* command) {
  const CliIo& io = ctx.io;
  RecipeBuild b;
  b.out_dir = ctx.out_root() / recipe.name;
  Cache cache(ctx.fs, ctx.cache_root());
  ProgressPrinter progress(io.err, io.err_is_terminal, ctx.clock);
  BuildEnv env{ctx.fs, cache, b.out_dir, ctx.clock, io.cancel, &progress};
  BuildOptions opt;
  opt.jobs = jobs;
  opt.targets = targets;
  std::string error;
  b.summary = run_build(recipe, env, opt, &error);
  progress.stop();
  if (!error.empty()) {
    std::fprintf(io.err, "error: %s\n", error.c_str());
    b.exit_code = kExitUsage;
  } else if (b.summary.interrupted()) {
    b.exit_code = kExitInterrupted;
  } else if (!b.summary.ok()) {
    std::fprintf(io.err, "%s: the inputs did not build (%s); nothing was checked\n", command,
                 summary_line(b.summary).c_str());
    b.exit_code = kExitBuildFailed;
  }
  return b;
}

InputArtifact input_artifact(const Recipe& recipe, const RecipeBuild& built, const std::string& node) {
  const NodeDecl* n = recipe.find(node);
  InputArtifact a{node, n ? n->stage->info().output_type : std::string(), {}};
  if (const NodeReport* r = built.report(node))
    for (const auto& o : r->outputs)
      a.files.push_back({o.name, built.out_dir / node / o.name, o.digest.hash});
  return a;
}

}  // namespace sylva
