// `sylva verify`: load → build the inputs → verify each node outside the cache → report →
// optionally accept the new images. The recipe, node selection, build and report directory are
// CheckCommand's (app/check_command.h). The verdicts come from the same core and the same
// parameter reading as stage `verify` (stages/verify/verify_stage.h), so the command and the
// stage agree.
#include "app/verify_command.h"

#include <filesystem>
#include <string>
#include <vector>

#include "app/check_command.h"
#include "app/gfx_module.h"
#include "libs/render/camera.h"
#include "stages/verify/report.h"
#include "stages/verify/verify_core.h"
#include "stages/verify/verify_stage.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr CheckCommandSpec kSpec{
    "verify",
    "verify",
    "docs/stages/verify.md",
    "verify-reports",
    gfx_command_summary("verify"),
    "verify only this node (repeatable; default: every node of stage verify)",
    "parallel nodes while building the inputs (default: all cores)",
    "where reports go (default: <out>/<recipe>/verify-reports)",
    nullptr,  // no --no-images: the renderings are the report
};

class VerifyCommand final : public CheckCommand {
 public:
  VerifyCommand() : CheckCommand(kSpec) {}

 protected:
  void add_mode_options(CLI::App& sub) override {
    sub.add_flag(
        "--update-refs", update_refs_,
        "copy the new renderings of views that failed or had no reference into the references directory");
  }

  // The verify nodes' inputs, not the nodes themselves: check_node runs them here.
  std::vector<std::string> targets(const std::vector<const NodeDecl*>& selected) const override {
    std::vector<std::string> out;
    for (const NodeDecl* n : selected)
      for (const auto& up : n->needs) out.push_back(up);
    return out;
  }

  // Verifies the node into its report directory, then reports and, with --update-refs, accepts
  // the new images.
  int check_node(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                 const fs::path& report_dir, CommandContext& ctx) override {
    // The node's inputs, exactly as the executor hands them to the stage.
    std::vector<InputArtifact> inputs;
    for (const auto& up : node.needs) {
      if (!built.report(up)) return fail_node(node, report_dir, "input '" + up + "' was not built", ctx);
      inputs.push_back(input_artifact(recipe, built, up));
    }
    const fs::path references = node.files.at("references");
    verify::Report report;
    const int rc = guarded(node, report_dir, ctx, [&] {
      const render::CameraSet cameras = render::load_camera_set(node.files.at("cameras"));
      const std::vector<verify::Asset> assets = verify::assets_from_inputs(inputs);
      if (ctx.cancelled()) throw Cancelled();
      StagedReportDir staged(ctx.fs, report_dir);
      const auto output_path = [&](const std::string& file) { return staged.path() / file; };
      const verify::RunEnv env{verify::shared_renderer(), output_path, [&] {
                                 if (ctx.cancelled()) throw Cancelled();
                               }};
      report = verify::run_verification(assets, cameras, references,
                                        verify::thresholds_from_params(node.params), env);
      verify::write_reports(report, output_path);
      if (ctx.cancelled()) throw Cancelled();
      staged.commit();
      return kExitOk;
    });
    if (rc != kExitOk) return rc;
    if (update_refs_ && ctx.cancelled()) return kExitInterrupted;  // references untouched
    return report_cases(node, report, references, report_dir, ctx);
  }

 private:
  // The views that did not pass (stderr; with --update-refs their renderings are copied into the
  // references first), then the verdict and where to look (stdout).
  int report_cases(const NodeDecl& node, const verify::Report& report, const fs::path& references,
                   const fs::path& report_dir, CommandContext& ctx) const {
    const CliIo& io = ctx.io;
    std::size_t open = 0, updated = 0;
    for (const auto& c : report.cases) {
      if (c.status == verify::CaseStatus::kPassed) continue;
      // Renderings exist for failed, missing and unreadable-reference cases, not for broken assets.
      if (update_refs_ && !c.image_file.empty()) {
        if (ctx.fs.copy_atomic(report_dir / c.image_file, references / c.image_file)) {
          ++updated;
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
                   u.c_str(), references.c_str(), node.name.c_str());
    const std::size_t total = report.cases.size();
    const std::size_t passed = report.count(verify::CaseStatus::kPassed);
    const char* verdict = open ? "FAILED" : updated ? "updated" : "passed";
    std::string counts = std::to_string(passed) + "/" + std::to_string(total) + " views passed";
    if (updated)
      counts += ", " + std::to_string(updated) + " reference" + (updated == 1 ? "" : "s") + " updated in " +
                references.string();
    if (open) counts += ", " + std::to_string(open) + " did not pass";
    std::fprintf(io.out, "sylva verify: node '%s' %s (%s); report: %s\n", node.name.c_str(), verdict,
                 counts.c_str(), (report_dir / "report.html").c_str());
    return open == 0 ? kExitOk : kExitBuildFailed;
  }

  bool update_refs_ = false;
};

}  // namespace

std::unique_ptr<CliCommand> make_verify_command() { return std::make_unique<VerifyCommand>(); }

}  // namespace sylva
