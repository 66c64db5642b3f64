// `sylva lodcheck`: load → build the lod (and forest) nodes → per node, the full-detail model
// (the node's full.glb, app/full_detail.h) and the written levels → render and compare
// (stages/lod/check) → table, JSON, images. The recipe, node selection, build and report
// directory are CheckCommand's (app/check_command.h); the pixel threshold comes from the node's
// parameters through the stage's own reading (chain_options_from_params).
#include "app/lodcheck_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "app/check_command.h"
#include "app/full_detail.h"
#include "app/gfx_module.h"
#include "libs/image/coverage.h"
#include "libs/image/image_io.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/render/camera.h"
#include "libs/render/forest_view.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "stages/forest/check/forestcheck.h"
#include "stages/lod/check/lodcheck.h"
#include "stages/lod/lod_stage.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr const char* kLodStage = "lod";
constexpr const char* kForestStage = "forest";

constexpr CheckCommandSpec kSpec{
    "lodcheck",
    kLodStage,
    "docs/stages/lod.md",
    "lodcheck",
    gfx_command_summary("lodcheck"),
    "check only this lod node (repeatable; default: every node of stage lod)",
    "parallel nodes while building (default: all cores)",
    "where reports and images go (default: <out>/<recipe>/lodcheck)",
    "do not write the renders and heat maps (lodcheck.json only)",
};

// JSON has no infinity: identical images have PSNR +inf.
nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// A view's coverage and colour numbers under the report's key names (shared by tree and forest views).
nlohmann::json footprint_json(const image::FootprintStats& s) {
  return {{"footprint_pixels", s.footprint_pixels},
          {"coverage_failing_fraction", s.failing_fraction},
          {"coverage_mean_error", s.coverage_mean_error},
          {"coverage_bias", s.coverage_bias},
          {"colour_mean_error", s.colour_mean_error}};
}

// One view's entry in lodcheck.json: `fields`, its verdict and its footprint_json numbers.
nlohmann::json view_json(nlohmann::json fields, bool passed, const std::string& failure,
                         const image::FootprintStats& s) {
  fields["passed"] = passed;
  fields["failure"] = failure;
  fields.update(footprint_json(s));
  return fields;
}

// A forest check's lodcheck.json.
nlohmann::json forest_json(const NodeDecl& node, const forest::ForestCheckOptions& fo,
                           const std::vector<forest::ForestViewCheck>& results) {
  nlohmann::json j;
  j["node"] = node.name;
  j["image"] = {
      {"width", fo.width_px}, {"height", fo.height_px}, {"supersample", fo.supersample}, {"msaa", fo.msaa}};
  j["thresholds"] = {{"pixel_threshold", fo.pixel_threshold},
                     {"max_failing_fraction", fo.max_failing_fraction},
                     {"max_coverage_error", fo.max_coverage_error}};
  nlohmann::json views = nlohmann::json::array();
  bool passed = true;
  for (const auto& c : results) {
    passed = passed && c.passed;
    views.push_back(view_json({{"view", c.view},
                               {"trees_drawn", c.trees_drawn},
                               {"trees_per_level", c.per_level},
                               {"lod_primitives", c.lod_primitives},
                               {"full_primitives", c.full_primitives}},
                              c.passed, c.failure, c.stats));
  }
  j["views"] = views;
  j["passed"] = passed;
  return j;
}

// A forest check's table on io.out; returns the exit code.
int print_forest_table(const NodeDecl& node, const forest::ForestCheckOptions& fo,
                       const std::vector<forest::ForestViewCheck>& results, const fs::path& report_dir,
                       const CliIo& io) {
  const char* name = node.name.c_str();
  std::fprintf(io.out,
               "lodcheck %s (forest): %dx%d px, a view passes when <= %.2f%% of the forest's pixels change "
               "coverage by "
               "> %.3g and the mean coverage change is <= %.3g\n",
               name, fo.width_px, fo.height_px, 100 * fo.max_failing_fraction, fo.pixel_threshold,
               fo.max_coverage_error);
  std::fprintf(io.out, "  %-10s %6s %12s %12s %8s %9s %7s %8s %8s  %s\n", "view", "trees", "lod_prims",
               "full_prims", "prims%", "footprint", "fail%", "cov_mean", "cov_bias", "verdict");
  std::size_t failed = 0;
  for (const auto& c : results) {
    failed += c.passed ? 0 : 1;
    const double pct = c.full_primitives ? 100.0 * (double(c.lod_primitives) - double(c.full_primitives)) /
                                               double(c.full_primitives)
                                         : 0;
    std::fprintf(io.out, "  %-10s %6zu %12zu %12zu %+7.1f%% %9zu %7.3f %8.5f %+8.5f  %s\n", c.view.c_str(),
                 c.trees_drawn, c.lod_primitives, c.full_primitives, pct, c.stats.footprint_pixels,
                 100 * c.stats.failing_fraction, c.stats.coverage_mean_error, c.stats.coverage_bias,
                 c.passed ? "ok" : ("FAIL: " + c.failure).c_str());
  }
  std::fprintf(io.out, "sylva lodcheck: node '%s' %s (%zu/%zu views passed); report: %s\n", name,
               failed ? "FAILED" : "passed", results.size() - failed, results.size(),
               (report_dir / "lodcheck.json").c_str());
  return failed ? kExitBuildFailed : kExitOk;
}

class LodcheckCommand final : public CheckCommand {
 public:
  LodcheckCommand() : CheckCommand(kSpec) {}

 protected:
  void add_options(CLI::App& sub) override {
    pixel_threshold_opt_ = add_coverage_thresholds(
        sub, options_.pixel_threshold, options_.max_failing_fraction, options_.max_coverage_error);
    sub.add_option("--supersample", options_.supersample,
                   "render at this multiple of the image height and average down (1 = off)")
        ->capture_default_str()
        ->check(CLI::Range(1, 8));
    sub.add_option("--azimuth", azimuths_, "view azimuths in degrees (repeatable; default: 0 and 90)")
        ->check(CLI::Range(-360.0, 360.0));
    sub.add_flag("--branches-only", branches_only_, "draw bark and branch lines only (no leaves or needles)");
    sub.add_option("--candidates", candidates_dir_,
                   "also measure another simplifier's models DIR/lod<i>.glb or .gltf (reported, not judged)");
    sub.add_option("--candidate-label", candidate_label_,
                   "name of the candidates in the report (default: DIR's name)");
    sub.add_option("--write-full", write_full_,
                   "write the full-detail model as a GLB (with exactly one node)");
    sub.add_option("--forest-height", forest_height_px_,
                   "forest nodes: the check image's height in pixels (16:9; levels chosen for it)")
        ->capture_default_str()
        ->check(CLI::Range(16, 4320));
  }

  // Forest nodes (named, or every one when no --node is given) are checked as forests, after the
  // lod nodes; the rest must be lod nodes.
  std::optional<std::vector<const NodeDecl*>> select(const Recipe& recipe, CommandContext& ctx) override {
    const std::vector<std::string>& nodes = node_names();
    std::vector<std::string> lod_names;
    std::vector<const NodeDecl*> forests;
    for (const auto& name : nodes) {
      const NodeDecl* n = recipe.find(name);
      if (n && n->stage->info().name == kForestStage) {
        if (std::find(forests.begin(), forests.end(), n) == forests.end()) forests.push_back(n);
      } else {
        lod_names.push_back(name);
      }
    }
    if (nodes.empty())
      for (const auto& n : recipe.nodes)
        if (n.stage->info().name == kForestStage) forests.push_back(&n);
    std::optional<std::vector<const NodeDecl*>> selected = std::vector<const NodeDecl*>{};
    if (!lod_names.empty() || forests.empty() || nodes.empty()) {
      bool has_lod = false;
      for (const auto& n : recipe.nodes) has_lod = has_lod || n.stage->info().name == kLodStage;
      if (!lod_names.empty() || has_lod || forests.empty())
        selected = select_stage_nodes(recipe, recipe_file(), kLodStage, lod_names, kSpec.doc_page, ctx.io);
    }
    if (selected) selected->insert(selected->end(), forests.begin(), forests.end());
    return selected;
  }

  std::optional<int> check_usage(const Recipe& /*recipe*/, const std::vector<const NodeDecl*>& selected,
                                 CommandContext& ctx) override {
    const std::size_t lods =
        static_cast<std::size_t>(std::count_if(selected.begin(), selected.end(), [](const NodeDecl* n) {
          return n->stage->info().name == kLodStage;
        }));
    if ((!write_full_.empty() || !candidates_dir_.empty()) && lods != 1) {
      std::fprintf(
          ctx.io.err,
          "error: --write-full and --candidates need exactly one lod node (--node NODE); %zu selected\n",
          lods);
      return kExitUsage;
    }
    if (!candidates_dir_.empty()) {
      const auto st = ctx.fs.stat(candidates_dir_);
      if (!st || !st->is_dir) {
        std::fprintf(ctx.io.err, "error: --candidates %s: not a directory\n", candidates_dir_.c_str());
        return kExitUsage;
      }
    }
    if (!azimuths_.empty()) options_.azimuths_deg = azimuths_;
    return std::nullopt;
  }

  // The lod nodes, and for each forest the forest and what it needs (its lod nodes' trees too).
  std::vector<std::string> targets(const std::vector<const NodeDecl*>& selected) const override {
    std::vector<std::string> out;
    for (const NodeDecl* n : selected) {
      out.push_back(n->name);
      if (n->stage->info().name == kForestStage) out.insert(out.end(), n->needs.begin(), n->needs.end());
    }
    return out;
  }

  void prepare(CommandContext& /*ctx*/) override { renderer_ = render::Renderer::create_headless(); }

  int check_node(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                 const fs::path& report_dir, CommandContext& ctx) override {
    if (node.stage->info().name == kForestStage) return check_forest(recipe, built, node, report_dir, ctx);
    return check_lod(recipe, built, node, report_dir, ctx);
  }

 private:
  // The levels as written (lod<i> files named by lod.json), then the candidates.
  std::vector<lod::CheckSubject> subjects_of(const InputArtifact& lod_out, const lodchain::LodChain& summary,
                                             CommandContext& ctx) const {
    std::vector<lod::CheckSubject> subjects;
    for (const lodchain::Level& l : summary.levels) {
      const std::size_t i = subjects.empty() ? 0 : subjects.back().level + 1;
      const ArtifactFile* f = lod_out.file(l.file);
      if (!f) throw std::runtime_error("the node wrote no " + l.file + " though lod.json lists it");
      lod::CheckSubject s{"sylva", i, l.epsilon_m, l.switch_distance_m, render::load_gltf_scene(f->path)};
      if (branches_only_) s.scene = lod::branches_only(s.scene);
      subjects.push_back(std::move(s));
    }
    if (candidates_dir_.empty()) return subjects;
    const std::string label =
        !candidate_label_.empty() ? candidate_label_ : fs::path(candidates_dir_).filename().string();
    const std::size_t n = subjects.size();
    for (std::size_t i = 0; i < n; ++i) {
      fs::path f = fs::path(candidates_dir_) / ("lod" + std::to_string(i) + ".glb");
      if (!ctx.fs.stat(f)) f.replace_extension(".gltf");
      if (!ctx.fs.stat(f)) continue;
      lod::CheckSubject s{label, i, subjects[i].epsilon, subjects[i].distance, render::load_gltf_scene(f)};
      if (branches_only_) s.scene = lod::branches_only(s.scene);
      subjects.push_back(std::move(s));
    }
    return subjects;
  }

  // --write-full: full.glb as the stage wrote it, or without leaves and needles.
  void write_full(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                  const std::string& glb, CommandContext& ctx) const {
    const std::string bytes =
        branches_only_ ? branches_only_glb(lod_full_detail_file(recipe, built, node.name)) : glb;
    if (!ctx.fs.write_atomic(write_full_, bytes)) throw std::runtime_error("cannot write " + write_full_);
  }

  int check_lod(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                const fs::path& report_dir, CommandContext& ctx) {
    std::vector<lod::ViewCheck> results;
    lod::ChainOptions chain;
    std::pair<std::size_t, std::size_t> full_counts;
    const int rc = guarded(node, report_dir, ctx, [&] {
      // The chain as written, and the full-detail model it was simplified from.
      const InputArtifact lod_out = input_artifact(recipe, built, node.name);
      const ArtifactFile* lod_json = lod_out.file("lod.json");
      if (!lod_json) return fail_node(node, report_dir, "the node wrote no lod.json", ctx);
      const lodchain::LodChain summary = lodchain::read_lod_chain(lod_json->path.string());
      chain = chain_options_from_params(node.params);
      const std::string glb = read_lod_full_detail(recipe, built, node.name, ctx);
      render::Scene full = render::load_gltf_scene_from_memory(glb, node.name + " (full detail)");
      if (branches_only_) full = lod::branches_only(full);
      if (ctx.cancelled()) throw Cancelled();
      if (!write_full_.empty()) write_full(recipe, built, node, glb, ctx);
      full_counts = {full.triangle_count(), full.line_count()};
      const std::vector<lod::CheckSubject> subjects = subjects_of(lod_out, summary, ctx);

      if (ctx.cancelled()) throw Cancelled();
      StagedReportDir staged(ctx.fs, report_dir);
      const fs::path& out = staged.path();
      const lod::CheckImageSink sink = [&](const lod::ViewCheck& c, const image::Image& ref,
                                           const image::Image& test, const image::Image& diff) {
        if (!keep_images(ctx)) return;
        const std::string stem = c.label + "_lod" + std::to_string(c.level) + "_" + c.view;
        if (c.label == "sylva")
          image::write_png(ref, out / ("full_lod" + std::to_string(c.level) + "_" + c.view + ".png"));
        image::write_png(test, out / (stem + ".png"));
        image::write_png(diff, out / (stem + "_diff.png"));
      };
      // An edge moved by delta pixels changes a pixel's coverage by at most delta.
      if (pixel_threshold_opt_->count() == 0) options_.pixel_threshold = std::min(1.0, chain.pixel_error);
      results = lod::check_subjects(*renderer_, full, subjects, chain.camera, options_, sink);
      write_json_report(out / "lodcheck.json", lod_json_report(node, summary, chain, full_counts, results),
                        ctx);
      if (ctx.cancelled()) throw Cancelled();
      staged.commit();
      return kExitOk;
    });
    if (rc != kExitOk) return rc;
    return print_table(node, chain, full_counts, results, report_dir, ctx.io);
  }

  // A forest (stages/forest/check/forestcheck.h): its LOD-selected views against every tree at
  // full detail, from its own cameras at the check's size, judged with this command's thresholds.
  int check_forest(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                   const fs::path& report_dir, CommandContext& ctx) {
    std::vector<forest::ForestViewCheck> results;
    forest::ForestCheckOptions fo;
    fo.supersample = options_.supersample;
    fo.max_failing_fraction = options_.max_failing_fraction;
    fo.max_coverage_error = options_.max_coverage_error;
    fo.height_px = forest_height_px_;
    fo.width_px = forest_height_px_ * 16 / 9;
    const int rc = guarded(node, report_dir, ctx, [&] {
      const InputArtifact out = input_artifact(recipe, built, node.name);
      const ArtifactFile* inst = out.file("instances.json");
      const ArtifactFile* cams = out.file("cameras.yaml");
      if (!inst || !cams)
        return fail_node(node, report_dir, "the node wrote no instances.json or cameras.yaml", ctx);
      render::ForestView view = render::ForestView::load(inst->path);
      // Species i is the node's i-th lod input (docs/stages/forest.md).
      std::size_t s = 0;
      double delta = 0.5;
      for (const auto& need : node.needs) {
        const NodeDecl* lod = recipe.find(need);
        if (!lod || lod->stage->info().name != kLodStage) continue;
        if (s >= view.forest().species.size()) break;
        view.set_full_detail(s, lod_full_detail_scene(recipe, built, lod->name, ctx));
        delta = chain_options_from_params(lod->params).pixel_error;
        ++s;
      }
      if (s != view.forest().species.size())
        return fail_node(node, report_dir, "its lod inputs do not match the species of instances.json", ctx);
      fo.pixel_threshold = pixel_threshold_opt_->count() ? options_.pixel_threshold : std::min(1.0, delta);
      const render::CameraSet set = render::load_camera_set(cams->path);
      const std::vector<render::Camera> cameras = render::forest_cameras(set, view.bounds());
      if (ctx.cancelled()) throw Cancelled();
      StagedReportDir staged(ctx.fs, report_dir);
      const fs::path& dir = staged.path();
      const forest::ForestCheckSink sink = [&](const forest::ForestViewCheck& c, const image::Image& full,
                                               const image::Image& lod, const image::Image& diff) {
        if (!keep_images(ctx)) return;
        image::write_png(full, dir / ("full_" + c.view + ".png"));
        image::write_png(lod, dir / ("lod_" + c.view + ".png"));
        image::write_png(diff, dir / ("lod_" + c.view + "_diff.png"));
      };
      results = forest::check_forest(view, *renderer_, cameras, fo, sink);
      if (!ctx.fs.write_atomic(dir / "lodcheck.json", forest_json(node, fo, results).dump(2) + "\n"))
        return fail_node(node, report_dir, "cannot write lodcheck.json", ctx);
      if (ctx.cancelled()) throw Cancelled();
      staged.commit();
      return kExitOk;
    });
    if (rc != kExitOk) return rc;
    return print_forest_table(node, fo, results, report_dir, ctx.io);
  }

  int print_table(const NodeDecl& node, const lod::ChainOptions& chain,
                  const std::pair<std::size_t, std::size_t>& full, const std::vector<lod::ViewCheck>& results,
                  const fs::path& report_dir, const CliIo& io) const {
    std::fprintf(io.out,
                 "lodcheck %s: camera %.4g deg, %d px, delta %.3g px; a view passes when <= %.2f%% of the "
                 "tree's pixels "
                 "change coverage by > %.3g and the mean coverage change is <= %.3g%s\n",
                 node.name.c_str(), chain.camera.fov_y_rad * 180 / std::numbers::pi, chain.camera.height_px,
                 chain.pixel_error, 100 * options_.max_failing_fraction, options_.pixel_threshold,
                 options_.max_coverage_error, branches_only_ ? " (branches only)" : "");
    std::fprintf(io.out, "  full detail: %zu triangles, %zu lines\n", full.first, full.second);
    std::fprintf(io.out, "  %-10s %5s %9s %9s %6s %10s %9s %7s %8s %8s %6s  %s\n", "model", "level", "eps_m",
                 "dist_m", "view", "primitives", "footprint", "fail%", "cov_mean", "cov_bias", "rgb_mean",
                 "verdict");
    std::size_t failed = 0, judged = 0;
    for (const auto& c : results) {
      const bool is_sylva = c.label == "sylva";
      if (is_sylva) {
        ++judged;
        failed += c.passed ? 0 : 1;
      }
      std::fprintf(io.out, "  %-10s %5zu %9.4f %9.2f %6s %10zu %9zu %7.3f %8.5f %+8.5f %8.5f  %s\n",
                   c.label.c_str(), c.level, c.epsilon, c.distance, c.view.c_str(), c.primitives,
                   c.stats.footprint_pixels, 100 * c.stats.failing_fraction, c.stats.coverage_mean_error,
                   c.stats.coverage_bias, c.stats.colour_mean_error,
                   !is_sylva  ? "-"
                   : c.passed ? "ok"
                              : ("FAIL: " + c.failure).c_str());
    }
    std::fprintf(io.out, "sylva lodcheck: node '%s' %s (%zu/%zu views passed); report: %s\n",
                 node.name.c_str(), failed ? "FAILED" : "passed", judged - failed, judged,
                 (report_dir / "lodcheck.json").c_str());
    return failed ? kExitBuildFailed : kExitOk;
  }

  nlohmann::json lod_json_report(const NodeDecl& node, const lodchain::LodChain& summary,
                                 const lod::ChainOptions& chain,
                                 const std::pair<std::size_t, std::size_t>& full,
                                 const std::vector<lod::ViewCheck>& results) const {
    nlohmann::json j;
    j["node"] = node.name;
    j["tree"] = summary.tree;
    j["camera"] = {{"fov_y_deg", chain.camera.fov_y_rad * 180 / std::numbers::pi},
                   {"height_px", chain.camera.height_px}};
    j["pixel_error_px"] = chain.pixel_error;
    j["thresholds"] = {{"pixel_threshold", options_.pixel_threshold},
                       {"max_failing_fraction", options_.max_failing_fraction},
                       {"max_coverage_error", options_.max_coverage_error},
                       {"supersample", options_.supersample},
                       {"msaa", options_.msaa}};
    j["branches_only"] = branches_only_;
    j["full_detail"] = {{"triangles", full.first}, {"lines", full.second}};
    nlohmann::json views = nlohmann::json::array();
    bool passed = true;
    for (const auto& c : results) {
      if (c.label == "sylva") passed = passed && c.passed;
      views.push_back(view_json({{"model", c.label},
                                 {"level", c.level},
                                 {"view", c.view},
                                 {"epsilon_m", c.epsilon},
                                 {"distance_m", c.distance},
                                 {"primitives", c.primitives},
                                 {"colour_max_error", c.colour.max_error},
                                 {"colour_psnr_db", finite_or_null(c.colour.psnr)},
                                 {"judged", c.label == "sylva"}},
                                c.passed, c.failure, c.stats));
    }
    j["views"] = views;
    j["passed"] = passed;
    return j;
  }

  std::unique_ptr<render::Renderer> renderer_;  // prepare()
  lod::LodCheckOptions options_;
  CLI::Option* pixel_threshold_opt_ = nullptr;
  std::vector<double> azimuths_;
  bool branches_only_ = false;
  std::string candidates_dir_, candidate_label_, write_full_;
  int forest_height_px_ = 540;
};

}  // namespace

std::unique_ptr<CliCommand> make_lodcheck_command() { return std::make_unique<LodcheckCommand>(); }

}  // namespace sylva
