// `sylva impostorcheck`: load → build the impostor nodes → per node, the full-detail model and
// the impostor as written → render and judge (stages/impostor/check) → table, JSON, images.
#include "app/impostorcheck_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/full_detail.h"
#include "app/gfx_module.h"
#include "app/recipe_build.h"
#include "app/report_dir.h"
#include "libs/image/image_io.h"
#include "libs/impostor/error_model.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/renderer.h"
#include "libs/render/shared_renderer.h"
#include "pipeline/filesystem.h"
#include "stages/impostor/check/impostorcheck.h"
#include "stages/impostor/check/subject.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr const char* kImpostorStage = "impostor";
constexpr const char* kReportsDir = "impostorcheck";

class ImpostorcheckCommand final : public CliCommand {
 public:
  explicit ImpostorcheckCommand(const StageRegistry& registry) : registry_(registry) {}

  CLI::App* add_to(CLI::App& app) override {
    parent_ = &app;
    auto* sub = app.add_subcommand("impostorcheck", gfx_command_summary("impostorcheck"));
    sub->add_option("recipe", recipe_, "recipe file (default: configs/default.yaml)");
    sub->add_option("--node", nodes_,
                    "check only this impostor node (repeatable; default: every node of stage impostor)")
        ->allow_extra_args(false);
    sub->add_option("-j,--jobs", jobs_, "parallel nodes while building (default: all cores)")
        ->check(CLI::Range(1, 1024));
    sub->add_option("--report-dir", report_root_,
                    "where reports and images go (default: <out>/<recipe>/impostorcheck)");
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
    sub->add_option(
           "--max-colour-error", options_.max_colour_error,
           "a view passes while the mean colour difference where both cover the pixel is at most this (0..1)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    sub->add_option("--azimuth", azimuths_, "view azimuths in degrees (repeatable; default: 7.5 + 30 k)")
        ->check(CLI::Range(-360.0, 360.0));
    sub->add_option("--elevation", elevations_, "view elevations in degrees (repeatable; default: 4, 33, 73)")
        ->check(CLI::Range(-90.0, 90.0));
    sub->add_option("--supersample", options_.supersample,
                    "render at this multiple and average down (1 = off)")
        ->capture_default_str()
        ->check(CLI::Range(1, 8));
    sub->add_option(
           "--distance-scale", options_.distance_scale,
           "check at this multiple of the switch distance (1 = the proof; < 1 shows where it breaks)")
        ->capture_default_str()
        ->check(CLI::Range(0.01, 100.0));
    sub->add_option(
           "--parallax-steps", options_.parallax_steps,
           "ray-march steps of the reference shader through each frame's depth map (0 = flat frames)")
        ->capture_default_str()
        ->check(CLI::Range(0, 64));
    sub->add_flag("--search-distance", search_,
                  "find the nearest distance at which the check passes: bisection over multiples of the "
                  "switch distance between --distance-scale S and S/16 (doubling S while it fails, to 64 S), "
                  "to 10 %; reports it and the check there (no images)");
    sub->add_flag("--no-images", no_images_,
                  "do not write the renders and heat maps (impostorcheck.json only)");
    return sub;
  }

  int run(const CliIo& io) override {
    RealFileSystem fsys;
    auto recipe = load_recipe_or_report(recipe_, registry_, fsys, io);
    if (!recipe) return kExitUsage;
    const auto selected =
        select_stage_nodes(*recipe, recipe_, kImpostorStage, nodes_, "docs/stages/impostor.md", io);
    if (!selected) return kExitUsage;
    start_scale_ = options_.distance_scale;
    if (!azimuths_.empty()) options_.azimuths_deg = azimuths_;
    if (!elevations_.empty()) options_.elevations_deg = elevations_;
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
    const RecipeBuild built =
        build_recipe_targets(*recipe, targets, parent_, jobs_, io, "sylva impostorcheck");
    if (built.exit_code == kExitInterrupted) return report_interrupted(io, "sylva impostorcheck");
    if (built.exit_code != kExitOk) return built.exit_code;

    render::Renderer* scene_renderer = nullptr;
    render::ImpostorRenderer* impostor_renderer = nullptr;
    try {
      scene_renderer = &render::shared_renderer();
      impostor_renderer = &render::shared_impostor_renderer();
    } catch (const render::RenderError& e) {
      std::fprintf(io.err, "error: %s\n", e.what());
      return kExitBuildFailed;
    }
    bool all_ok = true;
    for (const NodeDecl* node : *selected) {
      if (cancelled(io)) return report_interrupted(io, "sylva impostorcheck");
      const int rc = check_node(*recipe, *node, built, *scene_renderer, *impostor_renderer,
                                report_root / node->name, io);
      if (rc == kExitInterrupted) return report_interrupted(io, "sylva impostorcheck");
      all_ok = all_ok && rc == kExitOk;
    }
    return all_ok ? kExitOk : kExitBuildFailed;
  }

 private:
  int check_node(const Recipe& recipe, const NodeDecl& node, const RecipeBuild& built,
                 render::Renderer& scene_renderer, render::ImpostorRenderer& impostor_renderer,
                 const fs::path& report_dir, const CliIo& io) {
    auto fail = [&](const std::string& what) {
      std::fprintf(io.err, "error: node '%s' (stage impostor): %s\n", node.name.c_str(), what.c_str());
      std::error_code ec;
      fs::remove_all(report_dir, ec);  // an older run's report must not pass for this one's
      return kExitBuildFailed;
    };
    std::optional<StagedReportDir> staged;
    impostor::ImpostorCheckResult results;
    impostor::ImpostorSubject subject;
    impostor::ColourBaseline baseline;
    render::Scene baseline_scene;
    std::string reference;
    std::size_t full_triangles = 0, full_lines = 0;
    try {
      const InputArtifact out = input_artifact(recipe, built, node.name);
      const ArtifactFile* json = out.file("impostor.json");
      if (!json) return fail("the node wrote no impostor.json");
      subject = impostor::load_impostor_subject(json->path.parent_path(), "impostor");
      // The full detail of what was baked.
      const std::string& source = node.needs.at(0);
      const NodeDecl* src = recipe.find(source);
      render::Scene full;
      if (src && src->stage && src->stage->info().name == "lod") {
        full = render::load_gltf_scene_from_memory(lod_full_detail_glb(recipe, built, *src),
                                                   source + " (full detail)");
        reference = source + " (lod chain at epsilon 0)";
        // The chain's coarsest level, which the impostor replaces: the colour baseline.
        const InputArtifact lod = input_artifact(recipe, built, source);
        const ArtifactFile* summary = lod.file("lod.json");
        if (!summary) return fail("input '" + source + "' has no lod.json");
        const std::string coarsest = lodchain::read_lod_chain(summary->path.string()).levels.back().file;
        const ArtifactFile* last = lod.file(coarsest);
        if (!last) return fail("input '" + source + "' lacks " + coarsest + ", which its lod.json lists");
        baseline_scene = render::load_gltf_scene(last->path);
        baseline.scene = &baseline_scene;
        baseline.label = coarsest;
      } else {
        const InputArtifact mesh = input_artifact(recipe, built, source);
        std::vector<const ArtifactFile*> files = mesh.files_with_suffix(".glb");
        for (const ArtifactFile* f : mesh.files_with_suffix(".gltf")) files.push_back(f);
        if (files.size() != 1) return fail("input '" + source + "' must hold exactly one .glb or .gltf file");
        full = render::load_gltf_scene(files.front()->path);
        reference = source + " (" + files.front()->name + ")";
      }
      full_triangles = full.triangle_count();
      full_lines = full.line_count();

      if (cancelled(io)) throw Cancelled();
      staged.emplace(report_dir);
      const fs::path& dir = staged->path();
      // Called after every rendered view: where Ctrl-C or SIGTERM stops the check.
      const impostor::ImpostorImageSink sink = [&](const impostor::ImpostorViewCheck& c,
                                                   const image::Image& ref, const image::Image& test,
                                                   const image::Image& diff) {
        if (cancelled(io)) throw Cancelled();
        if (no_images_) return;
        image::write_png(ref, dir / ("full_" + c.view + ".png"));
        image::write_png(test, dir / ("impostor_" + c.view + ".png"));
        image::write_png(diff, dir / ("impostor_" + c.view + "_diff.png"));
      };
      if (pixel_threshold_opt_->count() == 0)
        options_.pixel_threshold = std::min(1.0, subject.info.pixel_error_px);
      std::optional<impostor::DistanceSearchResult> search;
      if (search_) {
        const impostor::DistanceStepSink step_sink = [&](const impostor::DistanceSearchStep& st) {
          if (cancelled(io)) throw Cancelled();
          std::fprintf(io.out, "  search %s: x%.4f = %.1f m %s%s\n", node.name.c_str(), st.scale,
                       st.distance_m, st.passed ? "passed" : "FAILED: ", st.passed ? "" : st.failure.c_str());
          std::fflush(io.out);
        };
        // The search starts at --distance-scale (billboards: far below the error model's distance,
        // where they are degenerate) and goes down to a 16th of it.
        impostor::DistanceSearchOptions range;
        range.hi = start_scale_;
        range.lo = start_scale_ / 16;
        search = impostor::find_proven_distance(scene_renderer, impostor_renderer, full, subject, options_,
                                                range, baseline, step_sink);
        results = search->at_proven;
        options_.distance_scale =
            search->proven_scale;  // for the report; the next node starts at start_scale_
      } else {
        results = impostor::check_impostor(scene_renderer, impostor_renderer, full, subject, options_,
                                           baseline, sink);
      }
      write_json(dir / "impostorcheck.json", node, subject.info, reference, full_triangles, full_lines,
                 baseline, results, search ? &*search : nullptr);
      if (search)
        std::fprintf(
            io.out,
            "sylva impostorcheck: node '%s' proven from %.1f m%s (x%.4f of the error model's %.1f m)\n",
            node.name.c_str(), search->proven_distance_m, search->below_lo ? " or nearer" : "",
            search->proven_scale, search->model_distance_m);
      if (search && search->proven_distance_m <= 0) {
        staged->commit();
        return fail("no distance up to 64 x the switch distance passes");
      }
      if (cancelled(io)) throw Cancelled();
      staged->commit();
    } catch (const Cancelled&) {
      return kExitInterrupted;
    } catch (const std::exception& e) {  // unreadable outputs, render failure, unwritable report
      return fail(e.what());
    }
    return print_table(node, subject.info, reference, full_triangles, full_lines, baseline, results,
                       report_dir, io);
  }

  // The error model's switch distance; impostor.json's differs when the recipe recorded one
  // (the stage's switch_distance_m, e.g. what --search-distance proved).
  static double model_distance(const impostor::ImpostorInfo& info) {
    return impostor::switch_distance(info.camera, info.error, info.pixel_error_px);
  }
  static std::string recorded_text(const impostor::ImpostorInfo& info) {
    const double model = model_distance(info);
    if (std::abs(info.switch_distance_m - model) <= 1e-6 * model) return "";
    char buf[96];
    std::snprintf(buf, sizeof buf, " (recorded by the recipe; the error model's: %.1f m)", model);
    return buf;
  }

  int print_table(const NodeDecl& node, const impostor::ImpostorInfo& info, const std::string& reference,
                  std::size_t full_triangles, std::size_t full_lines,
                  const impostor::ColourBaseline& baseline, const impostor::ImpostorCheckResult& result,
                  const fs::path& report_dir, const CliIo& io) const {
    const std::vector<impostor::ImpostorViewCheck>& results = result.views;
    const impostor::ErrorTerms& e = info.error;
    std::fprintf(
        io.out,
        "impostorcheck %s: %s, %s; epsilon %.4f m (source %.4f + texel %.4f + view %.4f), delta %.3g px, "
        "switch distance %.1f m%s%s\n",
        node.name.c_str(), impostor::kind_name(info.kind), grid_text(info).c_str(), e.epsilon_m(), e.source_m,
        e.texel_m, e.view_m, info.pixel_error_px, info.switch_distance_m, recorded_text(info).c_str(),
        options_.distance_scale != 1 ? (" (checked at x" + number(options_.distance_scale) + ")").c_str()
                                     : "");
    std::fprintf(
        io.out,
        "  full detail: %s, %zu triangles, %zu lines; a view passes when <= %.2f%% of the tree's pixels "
        "change coverage by > %.3g, the mean coverage change is <= %.3g and the colour change is <= %s\n",
        reference.c_str(), full_triangles, full_lines, 100 * options_.max_failing_fraction,
        options_.pixel_threshold, options_.max_coverage_error,
        baseline.scene ? ("max(" + number(options_.max_colour_error) + ", " + number(options_.colour_ratio) +
                          " x " + baseline.label + "'s in the view)")
                             .c_str()
                       : number(options_.max_colour_error).c_str());
    if (baseline.scene)
      std::fprintf(
          io.out,
          "  %s (the level the impostor replaces) from the same cameras: colour change mean %.4f, max %.4f; "
          "the impostor's mean may exceed it by %.3g\n",
          baseline.label.c_str(), result.baseline_colour_mean, result.baseline_colour_max,
          options_.colour_tolerance);
    std::fprintf(io.out, "  %-14s %6s %6s %8s %9s %10s %9s %7s %8s %8s %8s %8s  %s\n", "view", "az", "el",
                 "frame", "dist_m", "primitives", "footprint", "fail%", "cov_mean", "cov_bias", "colour",
                 "allowed", "verdict");
    std::size_t failed = 0;
    for (const auto& c : results) {
      failed += c.passed ? 0 : 1;
      std::fprintf(io.out, "  %-14s %6.1f %6.1f %7.1f° %9.1f %10zu %9zu %7.3f %8.5f %+8.5f %8.5f %8.5f  %s\n",
                   c.view.c_str(), c.azimuth_deg, c.elevation_deg, c.frame_angle_deg, c.distance,
                   c.primitives, c.footprint_pixels, 100 * c.coverage_failing_fraction, c.coverage_mean_error,
                   c.coverage_bias, c.shade_mean_error, c.colour_bound,
                   c.passed ? "ok" : ("FAIL: " + c.failure).c_str());
    }
    std::fprintf(io.out, "  mean colour change over the views: %.4f%s\n", result.colour_mean,
                 result.failure.empty() ? "" : ("  FAIL: " + result.failure).c_str());
    const bool ok = result.passed();
    std::fprintf(io.out, "sylva impostorcheck: node '%s' %s (%zu/%zu views passed); report: %s\n",
                 node.name.c_str(), ok ? "passed" : "FAILED", results.size() - failed, results.size(),
                 (report_dir / "impostorcheck.json").c_str());
    return ok ? kExitOk : kExitBuildFailed;
  }

  static std::string read_text(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) throw std::runtime_error(p.string() + ": cannot open file");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  static std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }

  static std::string grid_text(const impostor::ImpostorInfo& info) {
    char buf[128];
    if (info.kind == impostor::Kind::kBillboards) {
      std::snprintf(buf, sizeof buf, "%zu cards of %d px", info.cards.size(), info.frame_px);
    } else {
      std::snprintf(buf, sizeof buf, "%dx%d frames of %d px", info.frames_per_side, info.frames_per_side,
                    info.frame_px);
    }
    return buf;
  }

  void write_json(const fs::path& file, const NodeDecl& node, const impostor::ImpostorInfo& info,
                  const std::string& reference, std::size_t full_triangles, std::size_t full_lines,
                  const impostor::ColourBaseline& baseline, const impostor::ImpostorCheckResult& result,
                  const impostor::DistanceSearchResult* search) const {
    const std::vector<impostor::ImpostorViewCheck>& results = result.views;
    nlohmann::json j;
    j["node"] = node.name;
    j["kind"] = impostor::kind_name(info.kind);
    j["camera"] = {{"fov_y_deg", info.camera.fov_y_rad * 180 / std::numbers::pi},
                   {"height_px", info.camera.height_px}};
    j["pixel_error_px"] = info.pixel_error_px;
    j["epsilon_m"] = {{"source", info.error.source_m},
                      {"texel", info.error.texel_m},
                      {"view", info.error.view_m},
                      {"total", info.error.epsilon_m()}};
    j["switch_distance_m"] = info.switch_distance_m;
    j["model_switch_distance_m"] = model_distance(info);
    j["distance_scale"] = options_.distance_scale;
    j["thresholds"] = {{"pixel_threshold", options_.pixel_threshold},
                       {"max_failing_fraction", options_.max_failing_fraction},
                       {"max_coverage_error", options_.max_coverage_error},
                       {"max_colour_error", options_.max_colour_error},
                       {"colour_ratio", options_.colour_ratio},
                       {"colour_tolerance", options_.colour_tolerance},
                       {"supersample", options_.supersample},
                       {"msaa", options_.msaa}};
    j["full_detail"] = {{"reference", reference}, {"triangles", full_triangles}, {"lines", full_lines}};
    if (baseline.scene)
      j["colour_baseline"] = {{"file", baseline.label},
                              {"colour_mean_error", result.baseline_colour_mean},
                              {"colour_max_error", result.baseline_colour_max}};
    nlohmann::json views = nlohmann::json::array();
    for (const auto& c : results) {
      views.push_back({{"view", c.view},
                       {"azimuth_deg", c.azimuth_deg},
                       {"elevation_deg", c.elevation_deg},
                       {"nearest_frame_deg", c.frame_angle_deg},
                       {"distance_m", c.distance},
                       {"primitives", c.primitives},
                       {"footprint_pixels", c.footprint_pixels},
                       {"coverage_failing_fraction", c.coverage_failing_fraction},
                       {"coverage_mean_error", c.coverage_mean_error},
                       {"coverage_bias", c.coverage_bias},
                       {"colour_mean_error", c.shade_mean_error},
                       {"colour_bound", c.colour_bound},
                       {"baseline_colour_mean_error", c.baseline_colour},
                       {"footprint_colour_mean_error", c.colour_mean_error},
                       {"passed", c.passed},
                       {"failure", c.failure}});
    }
    j["views"] = views;
    if (search) {
      nlohmann::json steps = nlohmann::json::array();
      for (const auto& st : search->steps)
        steps.push_back({{"scale", st.scale},
                         {"distance_m", st.distance_m},
                         {"passed", st.passed},
                         {"failure", st.failure}});
      j["distance_search"] = {{"model_distance_m", search->model_distance_m},
                              {"proven_distance_m", search->proven_distance_m},
                              {"proven_scale", search->proven_scale},
                              {"passed_at_smallest_scale", search->below_lo},
                              {"steps", steps}};
    }
    j["colour_mean_error"] = result.colour_mean;
    j["failure"] = result.failure;
    j["passed"] = result.passed();
    RealFileSystem fsys;
    if (!fsys.write_atomic(file, j.dump(2) + "\n")) throw std::runtime_error("cannot write " + file.string());
  }

  const StageRegistry& registry_;
  CLI::App* parent_ = nullptr;
  std::string recipe_ = "configs/default.yaml";
  std::vector<std::string> nodes_;
  int jobs_ = 0;
  std::string report_root_;
  impostor::ImpostorCheckOptions options_;
  CLI::Option* pixel_threshold_opt_ = nullptr;
  std::vector<double> azimuths_, elevations_;
  bool no_images_ = false;
  bool search_ = false;
  double start_scale_ = 1;  // --distance-scale as given (a search reports each node at its own)
};

}  // namespace

std::unique_ptr<CliCommand> make_impostorcheck_command(const StageRegistry& registry) {
  return std::make_unique<ImpostorcheckCommand>(registry);
}

}  // namespace sylva
