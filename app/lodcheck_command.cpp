// `sylva lodcheck`: load → build the lod nodes → per node, the full-detail model and the written
// levels → render and compare (stages/lod/check) → table, JSON, images. The chain options come
// from the node's parameters through the stage's own reading (chain_options_from_params), so
// the full-detail model is the one the stage's levels were simplified from.
#include "app/lodcheck_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "app/full_detail.h"
#include "app/gfx_module.h"
#include "app/recipe_build.h"
#include "app/report_dir.h"
#include "libs/image/coverage.h"
#include "libs/image/image_io.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/render/camera.h"
#include "libs/render/forest_view.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "pipeline/filesystem.h"
#include "stages/forest/check/forestcheck.h"
#include "stages/lod/chain.h"
#include "stages/lod/check/lodcheck.h"
#include "stages/lod/lod_stage.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr const char* kLodStage = "lod";
constexpr const char* kForestStage = "forest";
constexpr const char* kReportsDir = "lodcheck";

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

// The full-detail model of lod node `node` (app/full_detail.h) as a scene; `glb` receives the
// encoded file when not null.
render::Scene full_detail_scene(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                                bool branches_only, std::string* glb = nullptr) {
  std::string full_glb = lod_full_detail_glb(recipe, built, node, branches_only);
  if (glb) *glb = full_glb;
  render::Scene full = render::load_gltf_scene_from_memory(std::move(full_glb), node.name + " (full detail)");
  if (branches_only) full = lod::branches_only(full);
  return full;
}

class LodcheckCommand final : public CliCommand {
 public:
  explicit LodcheckCommand(const StageRegistry& registry) : registry_(registry) {}

  CLI::App* add_to(CLI::App& app) override {
    parent_ = &app;
    auto* sub = app.add_subcommand("lodcheck", gfx_command_summary("lodcheck"));
    sub->add_option("recipe", recipe_, "recipe file (default: configs/default.yaml)");
    sub->add_option("--node", nodes_,
                    "check only this lod node (repeatable; default: every node of stage lod)")
        ->allow_extra_args(false);
    sub->add_option("-j,--jobs", jobs_, "parallel nodes while building (default: all cores)")
        ->check(CLI::Range(1, 1024));
    sub->add_option("--report-dir", report_root_,
                    "where reports and images go (default: <out>/<recipe>/lodcheck)");
    pixel_threshold_opt_ = sub->add_option("--pixel-threshold", options_.pixel_threshold,
                                           "a pixel fails when its coverage changes by more than this (0..1; "
                                           "default: the node's pixel_error delta, at most 1)")
                               ->check(CLI::Range(0.0, 1.0));
    sub->add_option("--max-failing-fraction", options_.max_failing_fraction,
                    "a view passes while at most this fraction of the tree's pixels fail (0..1)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    sub->add_option(
           "--max-coverage-error", options_.max_coverage_error,
           "a view passes while the mean coverage change over the tree's pixels is at most this (0..1)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    sub->add_option("--supersample", options_.supersample,
                    "render at this multiple of the image height and average down (1 = off)")
        ->capture_default_str()
        ->check(CLI::Range(1, 8));
    sub->add_option("--azimuth", azimuths_, "view azimuths in degrees (repeatable; default: 0 and 90)")
        ->check(CLI::Range(-360.0, 360.0));
    sub->add_flag("--branches-only", branches_only_,
                  "draw bark and branch lines only (no leaves or needles)");
    sub->add_option(
        "--candidates", candidates_dir_,
        "also measure another simplifier's models DIR/lod<i>.glb or .gltf (reported, not judged)");
    sub->add_option("--candidate-label", candidate_label_,
                    "name of the candidates in the report (default: DIR's name)");
    sub->add_option("--write-full", write_full_,
                    "write the full-detail model as a GLB (with exactly one node)");
    sub->add_option("--forest-height", forest_height_px_,
                    "forest nodes: the check image's height in pixels (16:9; levels chosen for it)")
        ->capture_default_str()
        ->check(CLI::Range(16, 4320));
    sub->add_flag("--no-images", no_images_, "do not write the renders and heat maps (lodcheck.json only)");
    return sub;
  }

  int run(const CliIo& io) override {
    RealFileSystem fsys;
    auto recipe = load_recipe_or_report(recipe_, registry_, fsys, io);
    if (!recipe) return kExitUsage;
    // Forest nodes (named, or every one when no --node is given) are checked as forests; the rest
    // must be lod nodes.
    std::vector<std::string> lod_names;
    std::vector<const NodeDecl*> forests;
    for (const auto& name : nodes_) {
      const NodeDecl* n = recipe->find(name);
      if (n && n->stage->info().name == kForestStage) {
        if (std::find(forests.begin(), forests.end(), n) == forests.end()) forests.push_back(n);
      } else {
        lod_names.push_back(name);
      }
    }
    if (nodes_.empty())
      for (const auto& n : recipe->nodes)
        if (n.stage->info().name == kForestStage) forests.push_back(&n);
    std::optional<std::vector<const NodeDecl*>> selected = std::vector<const NodeDecl*>{};
    if (!lod_names.empty() || forests.empty() || nodes_.empty()) {
      bool has_lod = false;
      for (const auto& n : recipe->nodes) has_lod = has_lod || n.stage->info().name == kLodStage;
      if (!lod_names.empty() || has_lod || forests.empty())
        selected = select_stage_nodes(*recipe, recipe_, kLodStage, lod_names, "docs/stages/lod.md", io);
    }
    if (!selected) return kExitUsage;
    if ((!write_full_.empty() || !candidates_dir_.empty()) && selected->size() != 1) {
      std::fprintf(
          io.err,
          "error: --write-full and --candidates need exactly one lod node (--node NODE); %zu selected\n",
          selected->size());
      return kExitUsage;
    }
    if (!candidates_dir_.empty() && !fs::is_directory(candidates_dir_)) {
      std::fprintf(io.err, "error: --candidates %s: not a directory\n", candidates_dir_.c_str());
      return kExitUsage;
    }
    if (!azimuths_.empty()) options_.azimuths_deg = azimuths_;
    const std::string out_root = global_option(parent_, "--out").value_or("out");
    const fs::path out_dir = fs::path(out_root) / recipe->name;
    if (report_root_.empty() && recipe->find(kReportsDir)) {
      std::fprintf(io.err,
                   "error: recipe '%s' has a node named '%s', whose outputs would mix with the reports; "
                   "choose another directory with --report-dir\n",
                   recipe->name.c_str(), kReportsDir);
      return kExitUsage;
    }
    const fs::path report_root = report_root_.empty() ? out_dir / kReportsDir : fs::path(report_root_);

    std::vector<std::string> targets;
    for (const NodeDecl* n : *selected) targets.push_back(n->name);
    for (const NodeDecl* f : forests) {
      targets.push_back(f->name);
      for (const auto& need : f->needs) targets.push_back(need);  // lod nodes: their trees are needed too
    }
    const RecipeBuild built = build_recipe_targets(*recipe, targets, parent_, jobs_, io, "sylva lodcheck");
    if (built.exit_code == kExitInterrupted) return report_interrupted(io, "sylva lodcheck");
    if (built.exit_code != kExitOk) return built.exit_code;

    std::unique_ptr<render::Renderer> renderer;
    try {
      renderer = render::Renderer::create_headless();
    } catch (const render::RenderError& e) {
      std::fprintf(io.err, "error: %s\n", e.what());
      return kExitBuildFailed;
    }
    bool all_ok = true;
    for (const NodeDecl* node : *selected) {
      if (cancelled(io)) return report_interrupted(io, "sylva lodcheck");
      const int rc = check_node(*recipe, *node, built, *renderer, report_root / node->name, io);
      if (rc == kExitInterrupted) return report_interrupted(io, "sylva lodcheck");
      all_ok = all_ok && rc == kExitOk;
    }
    for (const NodeDecl* f : forests) {
      if (cancelled(io)) return report_interrupted(io, "sylva lodcheck");
      const int rc = check_forest_node(*recipe, *f, built, *renderer, report_root / f->name, io);
      if (rc == kExitInterrupted) return report_interrupted(io, "sylva lodcheck");
      all_ok = all_ok && rc == kExitOk;
    }
    return all_ok ? kExitOk : kExitBuildFailed;
  }

 private:
  int check_node(const Recipe& recipe, const NodeDecl& node, const RecipeBuild& built,
                 render::Renderer& renderer, const fs::path& report_dir, const CliIo& io) {
    const char* name = node.name.c_str();
    auto fail = [&](const std::string& what) {
      std::fprintf(io.err, "error: node '%s' (stage lod): %s\n", name, what.c_str());
      std::error_code ec;
      fs::remove_all(report_dir, ec);  // an older run's report must not pass for this one's
      return kExitBuildFailed;
    };
    std::optional<StagedReportDir> staged;
    std::vector<lod::ViewCheck> results;
    lod::ChainOptions chain;
    lodchain::LodChain summary;  // lod.json (libs/lodchain)
    std::pair<std::size_t, std::size_t> full_counts;
    try {
      // The chain as written, and the full-detail model of the tree it was built from.
      const InputArtifact lod_out = input_artifact(recipe, built, node.name);
      const ArtifactFile* lod_json = lod_out.file("lod.json");
      if (!lod_json) return fail("the node wrote no lod.json");
      summary = lodchain::read_lod_chain(lod_json->path.string());
      chain = chain_options_from_params(node.params);
      std::string full_glb;
      render::Scene full = full_detail_scene(recipe, built, node, branches_only_, &full_glb);
      if (cancelled(io)) throw Cancelled();
      if (!write_full_.empty()) {
        RealFileSystem fsys;
        if (!fsys.write_atomic(write_full_, full_glb)) return fail("cannot write " + write_full_);
      }
      full_counts = {full.triangle_count(), full.line_count()};

      // Subjects: the levels as written, then the candidates.
      std::vector<lod::CheckSubject> subjects;
      const std::string cand_label =
          !candidate_label_.empty() ? candidate_label_ : fs::path(candidates_dir_).filename().string();
      for (const lodchain::Level& l : summary.levels) {
        const std::size_t i = subjects.empty() ? 0 : subjects.back().level + 1;
        const ArtifactFile* f = lod_out.file(l.file);
        if (!f) return fail("the node wrote no " + l.file + " though lod.json lists it");
        lod::CheckSubject s{"sylva", i, l.epsilon_m, l.switch_distance_m, render::load_gltf_scene(f->path)};
        if (branches_only_) s.scene = lod::branches_only(s.scene);
        subjects.push_back(std::move(s));
      }
      if (!candidates_dir_.empty()) {
        const std::size_t n = subjects.size();
        for (std::size_t i = 0; i < n; ++i) {
          fs::path f = fs::path(candidates_dir_) / ("lod" + std::to_string(i) + ".glb");
          if (!fs::exists(f)) f.replace_extension(".gltf");
          if (!fs::exists(f)) continue;
          lod::CheckSubject s{cand_label, i, subjects[i].epsilon, subjects[i].distance,
                              render::load_gltf_scene(f)};
          if (branches_only_) s.scene = lod::branches_only(s.scene);
          subjects.push_back(std::move(s));
        }
      }

      if (cancelled(io)) throw Cancelled();
      staged.emplace(report_dir);
      const fs::path& out = staged->path();
      // Called after every rendered view: where Ctrl-C or SIGTERM stops the check.
      const lod::CheckImageSink sink = [&](const lod::ViewCheck& c, const image::Image& ref,
                                           const image::Image& test, const image::Image& diff) {
        if (cancelled(io)) throw Cancelled();
        if (no_images_) return;
        const std::string stem = c.label + "_lod" + std::to_string(c.level) + "_" + c.view;
        if (c.label == "sylva")
          image::write_png(ref, out / ("full_lod" + std::to_string(c.level) + "_" + c.view + ".png"));
        image::write_png(test, out / (stem + ".png"));
        image::write_png(diff, out / (stem + "_diff.png"));
      };
      // An edge moved by delta pixels changes a pixel's coverage by at most delta.
      if (pixel_threshold_opt_->count() == 0) options_.pixel_threshold = std::min(1.0, chain.pixel_error);
      results = lod::check_subjects(renderer, full, subjects, chain.camera, options_, sink);
      write_json(out / "lodcheck.json", node, summary, chain, full, results);
      if (cancelled(io)) throw Cancelled();
      staged->commit();
    } catch (const Cancelled&) {
      return kExitInterrupted;
    } catch (const std::exception& e) {  // unreadable tree or outputs, render failure, unwritable report
      return fail(e.what());
    }
    return print_table(node, chain, full_counts, results, report_dir, io);
  }

  // A forest (stages/forest/check/forestcheck.h): its LOD-selected views against every tree at
  // full detail, from its own cameras at the check's size, judged with this command's thresholds.
  int check_forest_node(const Recipe& recipe, const NodeDecl& node, const RecipeBuild& built,
                        render::Renderer& renderer, const fs::path& report_dir, const CliIo& io) {
    const char* name = node.name.c_str();
    auto fail = [&](const std::string& what) {
      std::fprintf(io.err, "error: node '%s' (stage forest): %s\n", name, what.c_str());
      std::error_code ec;
      fs::remove_all(report_dir, ec);  // an older run's report must not pass for this one's
      return kExitBuildFailed;
    };
    std::optional<StagedReportDir> staged;
    std::vector<forest::ForestViewCheck> results;
    forest::ForestCheckOptions fo;
    fo.supersample = options_.supersample;
    fo.max_failing_fraction = options_.max_failing_fraction;
    fo.max_coverage_error = options_.max_coverage_error;
    fo.height_px = forest_height_px_;
    fo.width_px = forest_height_px_ * 16 / 9;
    try {
      const InputArtifact out = input_artifact(recipe, built, node.name);
      const ArtifactFile* inst = out.file("instances.json");
      const ArtifactFile* cams = out.file("cameras.yaml");
      if (!inst || !cams) return fail("the node wrote no instances.json or cameras.yaml");
      render::ForestView view = render::ForestView::load(inst->path);
      // Species i is the node's i-th lod input (docs/stages/forest.md).
      std::size_t s = 0;
      double delta = 0.5;
      for (const auto& need : node.needs) {
        const NodeDecl* lod = recipe.find(need);
        if (!lod || lod->stage->info().name != kLodStage) continue;
        if (s >= view.forest().species.size()) break;
        view.set_full_detail(s, full_detail_scene(recipe, built, *lod, false));
        delta = chain_options_from_params(lod->params).pixel_error;
        ++s;
      }
      if (s != view.forest().species.size())
        return fail("its lod inputs do not match the species of instances.json");
      fo.pixel_threshold = pixel_threshold_opt_->count() ? options_.pixel_threshold : std::min(1.0, delta);
      const render::CameraSet set = render::load_camera_set(cams->path);
      const std::vector<render::Camera> cameras = render::forest_cameras(set, view.bounds());
      if (cancelled(io)) throw Cancelled();
      staged.emplace(report_dir);
      const fs::path& dir = staged->path();
      // Called after every rendered view: where Ctrl-C or SIGTERM stops the check.
      const forest::ForestCheckSink sink = [&](const forest::ForestViewCheck& c, const image::Image& full,
                                               const image::Image& lod, const image::Image& diff) {
        if (cancelled(io)) throw Cancelled();
        if (no_images_) return;
        image::write_png(full, dir / ("full_" + c.view + ".png"));
        image::write_png(lod, dir / ("lod_" + c.view + ".png"));
        image::write_png(diff, dir / ("lod_" + c.view + "_diff.png"));
      };
      results = forest::check_forest(view, renderer, cameras, fo, sink);
      nlohmann::json j;
      j["node"] = node.name;
      j["image"] = {{"width", fo.width_px},
                    {"height", fo.height_px},
                    {"supersample", fo.supersample},
                    {"msaa", fo.msaa}};
      j["thresholds"] = {{"pixel_threshold", fo.pixel_threshold},
                         {"max_failing_fraction", fo.max_failing_fraction},
                         {"max_coverage_error", fo.max_coverage_error}};
      nlohmann::json views = nlohmann::json::array();
      bool passed = true;
      for (const auto& c : results) {
        passed = passed && c.passed;
        views.push_back({{"view", c.view},
                         {"trees_drawn", c.trees_drawn},
                         {"trees_per_level", c.per_level},
                         {"lod_primitives", c.lod_primitives},
                         {"full_primitives", c.full_primitives},
                         {"passed", c.passed},
                         {"failure", c.failure}});
        views.back().update(footprint_json(c.stats));
      }
      j["views"] = views;
      j["passed"] = passed;
      RealFileSystem fsys;
      if (!fsys.write_atomic(dir / "lodcheck.json", j.dump(2) + "\n"))
        return fail("cannot write lodcheck.json");
      if (cancelled(io)) throw Cancelled();
      staged->commit();
    } catch (const Cancelled&) {
      return kExitInterrupted;
    } catch (const std::exception& e) {
      return fail(e.what());
    }
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

  void write_json(const fs::path& file, const NodeDecl& node, const lodchain::LodChain& summary,
                  const lod::ChainOptions& chain, const render::Scene& full,
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
    j["full_detail"] = {{"triangles", full.triangle_count()}, {"lines", full.line_count()}};
    nlohmann::json views = nlohmann::json::array();
    bool passed = true;
    for (const auto& c : results) {
      if (c.label == "sylva") passed = passed && c.passed;
      views.push_back({{"model", c.label},
                       {"level", c.level},
                       {"view", c.view},
                       {"epsilon_m", c.epsilon},
                       {"distance_m", c.distance},
                       {"primitives", c.primitives},
                       {"colour_max_error", c.colour.max_error},
                       {"colour_psnr_db", finite_or_null(c.colour.psnr)},
                       {"judged", c.label == "sylva"},
                       {"passed", c.passed},
                       {"failure", c.failure}});
      views.back().update(footprint_json(c.stats));
    }
    j["views"] = views;
    j["passed"] = passed;
    RealFileSystem fsys;
    if (!fsys.write_atomic(file, j.dump(2) + "\n")) throw std::runtime_error("cannot write " + file.string());
  }

  const StageRegistry& registry_;
  CLI::App* parent_ = nullptr;
  std::string recipe_ = "configs/default.yaml";
  std::vector<std::string> nodes_;
  int jobs_ = 0;
  std::string report_root_;
  lod::LodCheckOptions options_;
  CLI::Option* pixel_threshold_opt_ = nullptr;
  std::vector<double> azimuths_;
  bool branches_only_ = false;
  std::string candidates_dir_, candidate_label_, write_full_;
  bool no_images_ = false;
  int forest_height_px_ = 540;
};

}  // namespace

std::unique_ptr<CliCommand> make_lodcheck_command(const StageRegistry& registry) {
  return std::make_unique<LodcheckCommand>(registry);
}

}  // namespace sylva
