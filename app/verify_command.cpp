// `sylva verify`: load → build the inputs → verify each node outside the cache → report →
// optionally accept the new images. The verdicts come from the same core and the same parameter
// reading as stage `verify` (stages/verify/verify_stage.h), so the command and the stage agree.
#include "app/verify_command.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "app/gfx_module.h"
#include "app/recipe_build.h"
#include "app/report_dir.h"
#include "libs/render/camera.h"
#include "stages/verify/report.h"
#include "stages/verify/verify_core.h"
#include "stages/verify/verify_stage.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr const char* kVerifyStage = "verify";
constexpr const char* kReportsDir = "verify-reports";

class VerifyCommand final : public CliCommand {
 public:
  explicit VerifyCommand(const StageRegistry& registry) : registry_(registry) {}

  CLI::App* add_to(CLI::App& app) override {
    parent_ = &app;
    auto* sub = app.add_subcommand("verify", gfx_command_summary("verify"));
    sub->add_option("recipe", recipe_, "recipe file (default: configs/default.yaml)");
    sub->add_option("--node", nodes_,
                    "verify only this node (repeatable; default: every node of stage verify)")
        ->allow_extra_args(false);
    sub->add_flag(
        "--update-refs", update_refs_,
        "copy the new renderings of views that failed or had no reference into the references directory");
    sub->add_option("-j,--jobs", jobs_, "parallel nodes while building the inputs (default: all cores)")
        ->check(CLI::Range(1, 1024));
    sub->add_option("--report-dir", report_root_,
                    "where reports go (default: <out>/<recipe>/verify-reports)");
    return sub;
  }

  int run(const CliIo& io) override {
    RealFileSystem fsys;
    const std::string out_root = global_option(parent_, "--out").value_or("out");

    // 1. Load the recipe and pick the verify nodes.
    auto recipe = load_recipe_or_report(recipe_, registry_, fsys, io);
    if (!recipe) return kExitUsage;
    const auto selected =
        select_stage_nodes(*recipe, recipe_, kVerifyStage, nodes_, "docs/stages/verify.md", io);
    if (!selected) return kExitUsage;
    const fs::path out_dir = fs::path(out_root) / recipe->name;
    fs::path report_root = report_root_.empty() ? out_dir / kReportsDir : fs::path(report_root_);
    if (report_root_.empty() && recipe->find(kReportsDir)) {
      std::fprintf(io.err,
                   "error: recipe '%s' has a node named '%s', whose outputs would mix with the reports; "
                   "choose another directory with --report-dir\n",
                   recipe->name.c_str(), kReportsDir);
      return kExitUsage;
    }

    // 2. Build their inputs (not the verify nodes themselves: step 3 runs them here).
    std::vector<std::string> targets;
    for (const NodeDecl* n : *selected)
      for (const auto& up : n->needs) targets.push_back(up);
    const RecipeBuild built = build_recipe_targets(*recipe, targets, parent_, jobs_, io, "sylva verify");
    if (built.exit_code == kExitInterrupted) return report_interrupted(io, "sylva verify");
    if (built.exit_code != kExitOk) return built.exit_code;

    // 3. Verify each node; 4. accept new images when asked.
    bool all_ok = true;
    for (const NodeDecl* node : *selected) {
      if (cancelled(io)) return report_interrupted(io, "sylva verify");
      const int rc = verify_node(*recipe, *node, built, report_root / node->name, io);
      if (rc == kExitInterrupted) return report_interrupted(io, "sylva verify");
      all_ok = all_ok && rc == kExitOk;
    }
    return all_ok ? kExitOk : kExitBuildFailed;
  }

 private:
  int verify_node(const Recipe& recipe, const NodeDecl& node, const RecipeBuild& built,
                  const fs::path& report_dir, const CliIo& io) {
    const char* name = node.name.c_str();
    auto fail = [&](const std::string& what) {
      std::fprintf(io.err, "error: node '%s' (stage verify): %s\n", name, what.c_str());
      std::error_code ec;
      fs::remove_all(report_dir, ec);  // an older run's report must not pass for this one's
      return kExitBuildFailed;
    };
    std::optional<StagedReportDir> staged;
    // The node's inputs, exactly as the executor hands them to the stage.
    std::vector<InputArtifact> inputs;
    for (const auto& up : node.needs) {
      if (!built.report(up)) return fail("input '" + up + "' was not built");
      inputs.push_back(input_artifact(recipe, built, up));
    }
    const fs::path references = node.files.at("references");
    verify::Report report;
    try {
      const render::CameraSet cameras = render::load_camera_set(node.files.at("cameras"));
      const std::vector<verify::Asset> assets = verify::assets_from_inputs(inputs);
      if (cancelled(io)) throw Cancelled();
      staged.emplace(report_dir);
      const auto output_path = [&](const std::string& file) { return staged->path() / file; };
      const verify::RunEnv env{verify::shared_renderer(), output_path, [&] {
                                 if (cancelled(io)) throw Cancelled();
                               }};
      report = verify::run_verification(assets, cameras, references,
                                        verify::thresholds_from_params(node.params), env);
      verify::write_reports(report, output_path);
      if (cancelled(io)) throw Cancelled();
      staged->commit();
    } catch (const Cancelled&) {
      return kExitInterrupted;
    } catch (const std::exception& e) {  // camera set, inputs, no EGL, unwritable outputs
      return fail(e.what());
    }

    // Report: the views that did not pass, then the verdict and where to look.
    std::size_t open = 0, updated = 0;
    std::vector<std::string> updated_files;
    RealFileSystem fsys;
    if (update_refs_ && cancelled(io)) return kExitInterrupted;  // references untouched
    for (const auto& c : report.cases) {
      if (c.status == verify::CaseStatus::kPassed) continue;
      // Renderings exist for failed, missing and unreadable-reference cases, not for broken assets.
      if (update_refs_ && !c.image_file.empty()) {
        if (fsys.copy_atomic(report_dir / c.image_file, references / c.image_file)) {
          ++updated;
          updated_files.push_back(c.image_file);
          std::fprintf(io.err, "UPDATED %s/%s: %s\n", c.asset.c_str(), c.view.c_str(), c.message.c_str());
          continue;
        }
        std::fprintf(io.err, "error: cannot write %s\n", (references / c.image_file).c_str());
      }
      ++open;
      std::fprintf(io.err, "%s %s/%s: %s\n", c.status == verify::CaseStatus::kError ? "ERROR" : "FAIL",
                   c.asset.c_str(), c.view.c_str(), c.message.c_str());
    }
    for (const auto& u : report.unused_references)
      std::fprintf(io.err,
                   "note: %s in %s is not used by any view of node '%s' (delete it if the view is gone)\n",
                   u.c_str(), references.c_str(), name);
    const std::size_t total = report.cases.size();
    const std::size_t passed = report.count(verify::CaseStatus::kPassed);
    const char* verdict = open ? "FAILED" : updated ? "updated" : "passed";
    std::string counts = std::to_string(passed) + "/" + std::to_string(total) + " views passed";
    if (updated)
      counts += ", " + std::to_string(updated) + " reference" + (updated == 1 ? "" : "s") + " updated in " +
                references.string();
    if (open) counts += ", " + std::to_string(open) + " did not pass";
    std::fprintf(io.out, "sylva verify: node '%s' %s (%s); report: %s\n", name, verdict, counts.c_str(),
                 (report_dir / "report.html").c_str());
    return open == 0 ? kExitOk : kExitBuildFailed;
  }

  const StageRegistry& registry_;
  CLI::App* parent_ = nullptr;
  std::string recipe_ = "configs/default.yaml";
  std::vector<std::string> nodes_;
  bool update_refs_ = false;
  int jobs_ = 0;
  std::string report_root_;
};

}  // namespace

std::unique_ptr<CliCommand> make_verify_command(const StageRegistry& registry) {
  return std::make_unique<VerifyCommand>(registry);
}

}  // namespace sylva
