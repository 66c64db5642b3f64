// Subcommands: build, graph, explain, stages, cache {stats,gc,verify}, clean.
// Each is a straight sequence: load (recipe errors -> exit 2) → act → report.
#include "app/cli.h"

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/progress.h"
#include "pipeline/cache.h"
#include "pipeline/executor.h"
#include "pipeline/graph.h"
#include "pipeline/recipe_loader.h"

namespace sylva {

namespace fs = std::filesystem;

namespace {

std::string type_text(const ParamSpec& p) {
  std::string t = param_type_name(p.type);
  if (p.type == ParamType::kEnum) {
    t += " {";
    for (std::size_t i = 0; i < p.choices.size(); ++i) t += (i ? "," : "") + p.choices[i];
    t += "}";
  }
  if (p.min || p.max) {
    const bool integral = p.type == ParamType::kInt || p.type == ParamType::kIntList;
    auto num = [&](double d) {
      return integral ? std::to_string(static_cast<long long>(d)) : format_real(d);
    };
    t += " [" + (p.min ? num(*p.min) : std::string("-inf")) + ", " +
         (p.max ? num(*p.max) : std::string("inf")) + "]";
  }
  return t;
}

void print_params(std::FILE* out, const std::vector<ParamSpec>& params, const std::string& indent) {
  for (const auto& p : params) {
    std::fprintf(out, "%s%-22s %-28s %s%s\n", indent.c_str(), p.name.c_str(), type_text(p).c_str(),
                 p.required() ? "(required) " : ("= " + p.default_value.canonical() + "  ").c_str(),
                 p.doc.c_str());
    if (p.type == ParamType::kObject || p.type == ParamType::kObjectList)
      print_params(out, p.fields, indent + "  ");
  }
}

int cmd_stages(const StageRegistry& reg, const CliIo& io) {
  for (const Stage* s : reg.all()) {
    const StageInfo& i = s->info();
    std::string in;
    for (const auto& t : i.inputs.types) in += (in.empty() ? "" : "|") + t;
    const std::string count = i.inputs.max < 0 ? std::to_string(i.inputs.min) + "+"
                              : i.inputs.min == i.inputs.max
                                  ? std::to_string(i.inputs.min)
                                  : std::to_string(i.inputs.min) + "-" + std::to_string(i.inputs.max);
    std::fprintf(io.out, "%s (v%d): %s\n  inputs: %s  output: %s\n", i.name.c_str(), i.version,
                 i.summary.c_str(), in.empty() ? "none" : (count + " x " + in).c_str(),
                 i.output_type.c_str());
    print_params(io.out, i.params, "    ");
  }
  if (reg.all().empty()) std::fprintf(io.out, "no stages registered\n");
  return kExitOk;
}

int cmd_graph(const std::string& file, bool dot, CommandContext& ctx) {
  const CliIo& io = ctx.io;
  auto recipe = load_recipe_or_report(file, ctx);
  if (!recipe) return kExitUsage;
  BuildGraph g(*recipe);
  if (dot) {
    std::fprintf(io.out, "digraph \"%s\" {\n  rankdir=LR;\n", recipe->name.c_str());
    for (std::size_t i : g.topo_order())
      std::fprintf(io.out, "  \"%s\" [label=\"%s\\n(%s)\"];\n", recipe->nodes[i].name.c_str(),
                   recipe->nodes[i].name.c_str(), recipe->nodes[i].stage->info().name.c_str());
    for (std::size_t i : g.topo_order())
      for (const auto& up : recipe->nodes[i].needs)
        std::fprintf(io.out, "  \"%s\" -> \"%s\";\n", up.c_str(), recipe->nodes[i].name.c_str());
    std::fprintf(io.out, "}\n");
    return kExitOk;
  }
  for (std::size_t i : g.topo_order()) {
    const auto& n = recipe->nodes[i];
    std::string needs;
    for (const auto& u : n.needs) needs += (needs.empty() ? " <- " : ", ") + u;
    std::fprintf(io.out, "%s (%s)%s\n", n.name.c_str(), n.stage->info().name.c_str(), needs.c_str());
  }
  return kExitOk;
}

// "10G", "512M", "2048K", "1000" (bytes), "0" (never evict); nullopt if malformed.
std::optional<std::uint64_t> parse_size(const std::string& text) {
  if (text.empty()) return std::nullopt;
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const std::string unit = text.substr(used);
  double scale = 1;
  if (unit == "K" || unit == "KiB")
    scale = 1024.0;
  else if (unit == "M" || unit == "MiB")
    scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "GiB")
    scale = 1024.0 * 1024 * 1024;
  else if (!unit.empty() && unit != "B")
    return std::nullopt;
  if (v < 0) return std::nullopt;
  return static_cast<std::uint64_t>(v * scale);
}

struct BuildArgs {
  std::string recipe = "configs/default.yaml";
  std::string cache_max;  // --cache-max-size, else $SYLVA_CACHE_MAX_SIZE, else the default share
  int jobs = 0;
  std::vector<std::string> targets;
  bool keep_going = false, dry_run = false, json = false;
};

std::string human_bytes(std::uint64_t b);

// `clean --all` deletes only what sylva made (issue 15: `--out .` used to empty a project and
// `--cache ..` its parent): the cache if Cache::is_cache() accepts it, and in the output root
// each recipe directory (it has .sylva/) and the parse cache (.sylva-parse/); then the output
// root itself if nothing else is left in it. Everything else is kept and counted.
int cmd_clean_all(CommandContext& ctx) {
  FileSystem& fsys = ctx.fs;
  const CliIo& io = ctx.io;
  const fs::path cache = ctx.cache_root();
  std::size_t kept = 0;
  if (fsys.stat(cache)) {
    if (Cache::is_cache(fsys, cache)) {
      Cache tmp(fsys, cache);
      auto lock = tmp.lock_for_gc();  // waits for running builds
      fsys.remove_all(cache);
    } else {
      std::fprintf(io.err, "sylva clean: kept %s: not a sylva cache (no CACHEDIR.TAG written by sylva)\n",
                   escape_bytes(cache.string()).c_str());
      ++kept;
    }
  }
  const fs::path out = ctx.out_root();
  for (const auto& name : fsys.list(out)) {
    const fs::path p = out / name;
    auto st = fsys.stat(p);
    if (!st || !st->is_dir) {
      ++kept;
      continue;
    }
    if (p.lexically_normal() == cache.lexically_normal()) continue;  // judged above
    auto marker = fsys.stat(p / ".sylva");
    if (name == ".sylva-parse" || (marker && marker->is_dir))
      fsys.remove_all(p);
    else
      ++kept;
  }
  if (fsys.list(out).empty()) fsys.remove(out);
  if (kept > 0)
    std::fprintf(io.err, "sylva clean: kept %zu entr%s that sylva did not create (in %s)\n", kept,
                 kept == 1 ? "y" : "ies", escape_bytes(out.string()).c_str());
  return kExitOk;
}

int cmd_build(const BuildArgs& a, CommandContext& ctx) {
  const CliIo& io = ctx.io;
  auto recipe = load_recipe_or_report(a.recipe, ctx, ctx.options.out_dir);
  if (!recipe) return kExitUsage;
  Cache cache(ctx.fs, ctx.cache_root());
  ProgressPrinter progress(io.err, io.err_is_terminal, ctx.clock);
  const fs::path out_dir = ctx.out_root() / recipe->name;
  BuildEnv env{ctx.fs, cache, out_dir, ctx.clock, io.cancel, &progress};
  BuildOptions opt;
  opt.jobs = a.jobs;
  opt.keep_going = a.keep_going;
  opt.dry_run = a.dry_run;
  opt.targets = a.targets;
  std::string limit = a.cache_max;
  if (const char* env_limit = std::getenv("SYLVA_CACHE_MAX_SIZE"); limit.empty() && env_limit)
    limit = env_limit;
  if (!limit.empty()) {
    opt.cache_max_bytes = parse_size(limit);
    if (!opt.cache_max_bytes) {
      std::fprintf(io.err, "error: cache size '%s' is not a size like 20G, 512M or 0\n", limit.c_str());
      return kExitUsage;
    }
  }
  std::string error;
  BuildSummary s = run_build(*recipe, env, opt, &error);
  progress.stop();
  if (!error.empty()) {
    std::fprintf(io.err, "error: %s\n", error.c_str());
    return kExitUsage;
  }
  if (a.json) std::fputs(summary_json(recipe->name, s).c_str(), io.out);
  for (const auto& e : s.errors) std::fprintf(io.err, "error: %s\n", e.c_str());
  for (const auto& name : s.removed)
    std::fprintf(io.err, "sylva: %s %s/%s/ (node '%s' is no longer in the recipe)\n",
                 a.dry_run ? "would remove" : "removed", out_dir.c_str(), name.c_str(), name.c_str());
  if (s.evicted.actions_removed > 0)
    std::fprintf(io.err, "sylva: cache above its limit: evicted %llu least recently used results (%s)\n",
                 static_cast<unsigned long long>(s.evicted.actions_removed),
                 human_bytes(s.evicted.bytes_freed).c_str());
  std::fprintf(io.err, "sylva: %s; outputs in %s/\n", summary_line(s).c_str(), out_dir.c_str());
  if (s.interrupted()) return kExitInterrupted;
  return s.ok() ? kExitOk : kExitBuildFailed;
}

int cmd_explain(const std::string& file, const std::string& node, CommandContext& ctx) {
  const CliIo& io = ctx.io;
  auto recipe = load_recipe_or_report(file, ctx, ctx.options.out_dir);
  if (!recipe) return kExitUsage;
  if (!recipe->find(node)) {
    std::vector<std::string> names;
    for (const auto& n : recipe->nodes) names.push_back(n.name);
    std::fprintf(io.err, "error: no node '%s' in recipe '%s'%s\n", node.c_str(), recipe->name.c_str(),
                 did_you_mean(node, names).c_str());
    return kExitUsage;
  }
  Cache cache(ctx.fs, ctx.cache_root());
  BuildEnv env{ctx.fs, cache, ctx.out_root() / recipe->name, ctx.clock, nullptr, nullptr};
  for (const auto& line : explain_node(*recipe, env, node)) std::fprintf(io.out, "%s\n", line.c_str());
  return kExitOk;
}

std::string human_bytes(std::uint64_t b) {
  char buf[32];
  if (b >= (1ull << 30))
    std::snprintf(buf, sizeof buf, "%.2f GiB", static_cast<double>(b) / (1ull << 30));
  else if (b >= (1ull << 20))
    std::snprintf(buf, sizeof buf, "%.2f MiB", static_cast<double>(b) / (1ull << 20));
  else if (b >= 1024)
    std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(b) / 1024);
  else
    std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(b));
  return buf;
}

}  // namespace

int report_interrupted(const CliIo& io, const char* command) {
  std::fprintf(io.err, "%s: interrupted; nothing more was written (earlier reports are as they were)\n",
               command);
  return kExitInterrupted;
}

std::optional<Recipe> load_recipe_or_report(const std::string& file, CommandContext& ctx,
                                            const std::string& out_dir) {
  const CliIo& io = ctx.io;
  LoadOptions options;
  if (!out_dir.empty()) options.parse_cache_dir = fs::path(out_dir) / ".sylva-parse";
  options.confine = !ctx.options.allow_outside_root;
  options.root = ctx.options.root;
  for (const auto& l : ctx.options.limits)
    if (auto why = set_limit(options.limits, l)) {
      std::fprintf(io.err, "error: --limit %s: %s\n", escape_bytes(l).c_str(), why->c_str());
      return std::nullopt;
    }
  Diagnostics diags(options.limits.errors);
  auto recipe = load_recipe(file, ctx.registry, ctx.fs, diags, options);
  if (!recipe) {
    std::fputs(diags.pretty().c_str(), io.err);
    std::fprintf(io.err, "%zu error%s in recipe %s\n", diags.size(), diags.size() == 1 ? "" : "s",
                 escape_bytes(file).c_str());
  }
  return recipe;
}

fs::path cache_root_for(const std::string& out_dir, const std::string& cache_dir) {
  if (!cache_dir.empty()) return cache_dir;
  if (const char* env = std::getenv("SYLVA_CACHE"); env && *env) return env;
  return fs::path(out_dir) / "cache";
}

void add_global_options(CLI::App& app, GlobalOptions& g) {
  app.add_option("--out", g.out_dir, "output root (default: out)");
  app.add_option("--cache", g.cache_dir, "cache directory (default: $SYLVA_CACHE or <out>/cache)");
  app.add_flag("--allow-outside-root", g.allow_outside_root,
               "let recipes name files outside their project root (trusted recipes only; docs/recipes.md)");
  app.add_option("--root", g.root, "confine every recipe to this directory, whatever its 'root:' key says");
  app.add_option(
         "--limit", g.limits,
         "raise a recipe limit: file-bytes, yaml-nodes, include-depth, matrix, nodes, errors (NAME=N)")
      ->allow_extra_args(false);
}

std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv, const CliIo& io) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help("", CLI::AppFormatMode::Normal).c_str(), io.out);
    return kExitOk;
  } catch (const CLI::ParseError& err) {
    if (err.get_exit_code() == 0) {
      std::ostringstream out, errs;
      app.exit(err, out, errs);
      std::fputs(out.str().c_str(), io.out);
      return kExitOk;
    }
    std::fprintf(io.err, "error: %s\nrun 'sylva --help' for usage\n", err.what());
    return kExitUsage;
  }
  return std::nullopt;
}

namespace {

// The engine's subcommands, each: its options (filled by parsing), then what it runs.

CLI::App* add_build_command(CLI::App& app, BuildArgs& build) {
  auto* b = app.add_subcommand("build", "build a recipe (default: configs/default.yaml)");
  b->add_option("recipe", build.recipe, "recipe file");
  b->add_option("-j,--jobs", build.jobs, "parallel nodes (default: all cores)")->check(CLI::Range(1, 1024));
  // One node per --target, so that `--target a recipe.yaml` keeps recipe.yaml the recipe.
  b->add_option("--target", build.targets,
                "build only this node and what it needs (repeatable; globs allowed)")
      ->allow_extra_args(false);
  b->add_flag("-k,--keep-going", build.keep_going, "build everything that does not depend on a failure");
  b->add_flag("-n,--dry-run", build.dry_run, "show what would build; run nothing");
  b->add_flag("--json", build.json, "print a machine-readable summary on stdout");
  b->add_option("--cache-max-size", build.cache_max,
                "evict least recently used results above this size after the build (e.g. 20G; 0: never; "
                "default: $SYLVA_CACHE_MAX_SIZE, else a quarter of free disk plus the cache)");
  return b;
}

struct GraphArgs {
  std::string recipe;
  bool dot = false;
};

CLI::App* add_graph_command(CLI::App& app, GraphArgs& graph) {
  auto* g = app.add_subcommand("graph", "print the recipe's node graph in build order");
  g->add_option("recipe", graph.recipe, "recipe file")->required();
  g->add_flag("--dot", graph.dot, "Graphviz dot output");
  return g;
}

struct ExplainArgs {
  std::string recipe, node;
};

CLI::App* add_explain_command(CLI::App& app, ExplainArgs& explain) {
  auto* e = app.add_subcommand("explain", "say why a node will rebuild");
  e->add_option("recipe", explain.recipe, "recipe file")->required();
  e->add_option("node", explain.node, "node name")->required();
  return e;
}

// `sylva cache stats|gc|verify`.
struct CacheCommands {
  CLI::App* stats = nullptr;
  CLI::App* gc = nullptr;
  CLI::App* verify = nullptr;
  double max_gib = 0;  // gc --max-size-gib
};

void add_cache_commands(CLI::App& app, CacheCommands& cache) {
  auto* cache_cmd = app.add_subcommand("cache", "inspect or trim the cache");
  cache_cmd->require_subcommand(1);
  cache.stats = cache_cmd->add_subcommand("stats", "count blobs, bytes and action results");
  cache.gc = cache_cmd->add_subcommand("gc", "delete unreferenced blobs and stale temp files");
  cache.gc
      ->add_option("--max-size-gib", cache.max_gib, "also evict least recently used results above this size")
      ->check(CLI::NonNegativeNumber);
  cache.verify = cache_cmd->add_subcommand("verify", "re-hash every blob, delete corrupt ones");
}

int cmd_cache_stats(CommandContext& ctx) {
  Cache cache(ctx.fs, ctx.cache_root());
  const CacheStats s = cache.stats();
  std::fprintf(ctx.io.out, "cache %s: %llu blobs (%s), %llu action results, %llu temp entries\n",
               cache.root().c_str(), static_cast<unsigned long long>(s.blobs),
               human_bytes(s.blob_bytes).c_str(), static_cast<unsigned long long>(s.actions),
               static_cast<unsigned long long>(s.tmp_entries));
  return kExitOk;
}

int cmd_cache_gc(double max_gib, CommandContext& ctx) {
  Cache cache(ctx.fs, ctx.cache_root());
  auto gc_lock = cache.lock_for_gc();  // waits for running builds; they wait for it
  const GcResult r = cache.gc(static_cast<std::uint64_t>(max_gib * (1ull << 30)));
  std::fprintf(ctx.io.out, "removed %llu action results, %llu blobs (%s), %llu temp entries\n",
               static_cast<unsigned long long>(r.actions_removed),
               static_cast<unsigned long long>(r.blobs_removed), human_bytes(r.bytes_freed).c_str(),
               static_cast<unsigned long long>(r.tmp_removed));
  return kExitOk;
}

int cmd_cache_verify(CommandContext& ctx) {
  Cache cache(ctx.fs, ctx.cache_root());
  auto gc_lock = cache.lock_for_gc();
  const VerifyResult v = cache.verify_all();
  std::fprintf(ctx.io.out, "%llu corrupt blob%s removed, %llu invalid action result%s removed\n",
               static_cast<unsigned long long>(v.blobs_removed), v.blobs_removed == 1 ? "" : "s",
               static_cast<unsigned long long>(v.actions_removed), v.actions_removed == 1 ? "" : "s");
  return v.blobs_removed + v.actions_removed ? kExitBuildFailed : kExitOk;
}

struct CleanArgs {
  std::string recipe;
  bool all = false;
};

CLI::App* add_clean_command(CLI::App& app, CleanArgs& clean) {
  auto* cl = app.add_subcommand("clean", "delete a recipe's outputs (or, with --all, out/ and the cache)");
  cl->add_option("recipe", clean.recipe, "recipe whose out/<name>/ to delete");
  cl->add_flag("--all", clean.all, "delete every output and the cache");
  return cl;
}

int cmd_clean(const CleanArgs& clean, CommandContext& ctx) {
  if (clean.all) return cmd_clean_all(ctx);
  if (clean.recipe.empty()) {
    std::fprintf(ctx.io.err, "error: 'sylva clean' needs a recipe or --all\n");
    return kExitUsage;
  }
  auto recipe = load_recipe_or_report(clean.recipe, ctx);
  if (!recipe) return kExitUsage;
  ctx.fs.remove_all(ctx.out_root() / recipe->name);
  return kExitOk;
}

}  // namespace

int run_cli(int argc, const char* const* argv, CommandContext& ctx, const std::vector<CliCommand*>& extra) {
  CLI::App app{"sylva: a headless batch asset pipeline for trees and forests"};
  app.require_subcommand(1);
  add_global_options(app, ctx.options);
  // Registration order is the order `sylva --help` lists the subcommands in.
  BuildArgs build;
  CLI::App* build_cmd = add_build_command(app, build);
  GraphArgs graph;
  CLI::App* graph_cmd = add_graph_command(app, graph);
  ExplainArgs explain;
  CLI::App* explain_cmd = add_explain_command(app, explain);
  CLI::App* stages_cmd = app.add_subcommand("stages", "list stages and their parameters");
  CacheCommands cache;
  add_cache_commands(app, cache);
  CleanArgs clean;
  CLI::App* clean_cmd = add_clean_command(app, clean);
  std::vector<std::pair<CLI::App*, CliCommand*>> extra_apps;
  for (CliCommand* c : extra) extra_apps.emplace_back(c->add_to(app), c);

  if (auto code = parse_command_line(app, argc, argv, ctx.io)) return *code;

  try {
    if (build_cmd->parsed()) return cmd_build(build, ctx);
    if (graph_cmd->parsed()) return cmd_graph(graph.recipe, graph.dot, ctx);
    if (explain_cmd->parsed()) return cmd_explain(explain.recipe, explain.node, ctx);
    if (stages_cmd->parsed()) return cmd_stages(ctx.registry, ctx.io);
    for (auto& [sub, cmd] : extra_apps)
      if (sub->parsed()) return cmd->run(ctx);
    if (cache.stats->parsed()) return cmd_cache_stats(ctx);
    if (cache.gc->parsed()) return cmd_cache_gc(cache.max_gib, ctx);
    if (cache.verify->parsed()) return cmd_cache_verify(ctx);
    if (clean_cmd->parsed()) return cmd_clean(clean, ctx);
  } catch (const std::exception& ex) {
    // Last line of defence: a clear message, never a stack trace.
    std::fprintf(ctx.io.err, "error: %s\n", ex.what());
    return kExitBuildFailed;
  }
  return kExitUsage;
}

}  // namespace sylva
