// The shared half of the check commands (check_command.h): the sequence every one of them runs
// and the lines it prints. Tests compare those lines byte for byte (tests/verify/cli_test.cpp,
// impostorcheck_cli_test.cpp, tests/engine/check_command_test.cpp), so a message here is a message
// of all three commands.
#include "app/check_command.h"

#include <cstdio>
#include <stdexcept>

namespace sylva {

namespace fs = std::filesystem;

CLI::App* CheckCommand::add_to(CLI::App& app) {
  auto* sub = app.add_subcommand(spec_.name, spec_.summary);
  sub->add_option("recipe", recipe_, "recipe file (default: configs/default.yaml)");
  sub->add_option("--node", nodes_, spec_.node_help)->allow_extra_args(false);
  add_mode_options(*sub);
  sub->add_option("-j,--jobs", jobs_, spec_.jobs_help)->check(CLI::Range(1, 1024));
  sub->add_option("--report-dir", report_root_, spec_.report_dir_help);
  add_options(*sub);
  if (spec_.no_images_help) sub->add_flag("--no-images", no_images_, spec_.no_images_help);
  return sub;
}

std::optional<std::vector<const NodeDecl*>> CheckCommand::select(const Recipe& recipe, CommandContext& ctx) {
  return select_stage_nodes(recipe, recipe_, spec_.stage, nodes_, spec_.doc_page, ctx.io);
}

std::vector<std::string> CheckCommand::targets(const std::vector<const NodeDecl*>& selected) const {
  std::vector<std::string> out;
  for (const NodeDecl* n : selected) out.push_back(n->name);
  return out;
}

int CheckCommand::run(CommandContext& ctx) {
  const CliIo& io = ctx.io;
  const std::string command = command_name();
  // 1-3. The recipe, the nodes, the command's own usage checks: all before anything is built.
  auto recipe = load_recipe_or_report(recipe_, ctx);
  if (!recipe) return kExitUsage;
  const auto selected = select(*recipe, ctx);
  if (!selected) return kExitUsage;
  if (auto code = check_usage(*recipe, *selected, ctx)) return *code;
  // 4. Where the reports go. A node of the reports' name would publish into the same directory.
  if (report_root_.empty() && recipe->find(spec_.reports_dir)) {
    std::fprintf(io.err,
                 "error: recipe '%s' has a node named '%s', whose outputs would mix with the reports; "
                 "choose another directory with --report-dir\n",
                 recipe->name.c_str(), spec_.reports_dir);
    return kExitUsage;
  }
  const fs::path report_root =
      report_root_.empty() ? ctx.out_root() / recipe->name / spec_.reports_dir : fs::path(report_root_);

  // 5. Build what the checks read, as `sylva build --target` would.
  const RecipeBuild built = build_recipe_targets(*recipe, targets(*selected), jobs_, ctx, command.c_str());
  if (built.exit_code == kExitInterrupted) return report_interrupted(io, command.c_str());
  if (built.exit_code != kExitOk) return built.exit_code;

  // 6-8. Check each node; every node is checked even after one failed.
  try {
    prepare(ctx);
  } catch (const std::exception& e) {  // e.g. no headless OpenGL
    std::fprintf(io.err, "error: %s\n", e.what());
    return kExitBuildFailed;
  }
  bool all_ok = true;
  for (const NodeDecl* node : *selected) {
    if (ctx.cancelled()) return report_interrupted(io, command.c_str());
    const int rc = check_node(*recipe, built, *node, report_root / node->name, ctx);
    if (rc == kExitInterrupted) return report_interrupted(io, command.c_str());
    all_ok = all_ok && rc == kExitOk;
  }
  return all_ok ? kExitOk : kExitBuildFailed;
}

int CheckCommand::fail_node(const NodeDecl& node, const fs::path& report_dir, const std::string& what,
                            CommandContext& ctx) const {
  std::fprintf(ctx.io.err, "error: node '%s' (stage %s): %s\n", node.name.c_str(),
               node.stage->info().name.c_str(), what.c_str());
  ctx.fs.remove_all(report_dir);
  return kExitBuildFailed;
}

int CheckCommand::guarded(const NodeDecl& node, const fs::path& report_dir, CommandContext& ctx,
                          const std::function<int()>& check) const {
  try {
    return check();
  } catch (const Cancelled&) {
    return kExitInterrupted;
  } catch (const std::exception& e) {
    return fail_node(node, report_dir, e.what(), ctx);
  }
}

bool CheckCommand::keep_images(const CommandContext& ctx) const {
  if (ctx.cancelled()) throw Cancelled();
  return !no_images_;
}

void CheckCommand::write_json_report(const fs::path& file, const nlohmann::json& json, CommandContext& ctx) {
  if (!ctx.fs.write_atomic(file, json.dump(2) + "\n"))
    throw std::runtime_error("cannot write " + file.string());
}

CLI::Option* CheckCommand::add_coverage_thresholds(CLI::App& sub, double& pixel_threshold,
                                                   double& max_failing_fraction, double& max_coverage_error) {
  CLI::Option* pixel = sub.add_option("--pixel-threshold", pixel_threshold,
                                      "a pixel fails when its coverage changes by more than this (0..1; "
                                      "default: the node's pixel_error delta, at most 1)")
                           ->check(CLI::Range(0.0, 1.0));
  sub.add_option("--max-failing-fraction", max_failing_fraction,
                 "a view passes while at most this fraction of the tree's pixels fail (0..1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub.add_option("--max-coverage-error", max_coverage_error,
                 "a view passes while the mean coverage change over the tree's pixels is at most this (0..1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  return pixel;
}

}  // namespace sylva
