// `sylva impostorcheck`: load → build the impostor nodes → per node, the full-detail model (for a
// lod input its full.glb, app/full_detail.h) and the impostor as written → render and judge
// (stages/impostor/check) → table, JSON, images. The recipe, node selection, build and report
// directory are CheckCommand's (app/check_command.h).
#include "app/impostorcheck_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "app/check_command.h"
#include "app/full_detail.h"
#include "app/gfx_module.h"
#include "libs/image/image_io.h"
#include "libs/impostor/error_model.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/renderer.h"
#include "libs/render/shared_renderer.h"
#include "stages/impostor/check/impostorcheck.h"
#include "stages/impostor/check/subject.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr CheckCommandSpec kSpec{
    "impostorcheck",
    "impostor",
    "docs/stages/impostor.md",
    "impostorcheck",
    gfx_command_summary("impostorcheck"),
    "check only this impostor node (repeatable; default: every node of stage impostor)",
    "parallel nodes while building (default: all cores)",
    "where reports and images go (default: <out>/<recipe>/impostorcheck)",
    "do not write the renders and heat maps (impostorcheck.json only)",
};

// What an impostor is judged against: the full detail of what it was baked from.
struct Reference {
  render::Scene scene;
  std::string label;  // in the table and the report: "lod_birch (lod chain at epsilon 0)"
  std::size_t triangles = 0, lines = 0;
};

class ImpostorcheckCommand final : public CheckCommand {
 public:
  ImpostorcheckCommand() : CheckCommand(kSpec) {}

 protected:
  void add_options(CLI::App& sub) override {
    pixel_threshold_opt_ = add_coverage_thresholds(
        sub, options_.pixel_threshold, options_.max_failing_fraction, options_.max_coverage_error);
    sub.add_option(
           "--max-colour-error", options_.max_colour_error,
           "a view passes while the mean colour difference where both cover the pixel is at most this (0..1)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    sub.add_option("--azimuth", azimuths_, "view azimuths in degrees (repeatable; default: 7.5 + 30 k)")
        ->check(CLI::Range(-360.0, 360.0));
    sub.add_option("--elevation", elevations_, "view elevations in degrees (repeatable; default: 4, 33, 73)")
        ->check(CLI::Range(-90.0, 90.0));
    sub.add_option("--supersample", options_.supersample,
                   "render at this multiple and average down (1 = off)")
        ->capture_default_str()
        ->check(CLI::Range(1, 8));
    sub.add_option("--distance-scale", options_.distance_scale,
                   "check at this multiple of the switch distance (1 = the proof; < 1 shows where it breaks)")
        ->capture_default_str()
        ->check(CLI::Range(0.01, 100.0));
    sub.add_option("--parallax-steps", options_.parallax_steps,
                   "ray-march steps of the reference shader through each frame's depth map (0 = flat frames)")
        ->capture_default_str()
        ->check(CLI::Range(0, 64));
    sub.add_flag("--search-distance", search_,
                 "find the nearest distance at which the check passes: bisection over multiples of the "
                 "switch distance between --distance-scale S and S/16 (doubling S while it fails, to 64 S), "
                 "to 10 %; reports it and the check there (no images)");
  }

  std::optional<int> check_usage(const Recipe& /*recipe*/, const std::vector<const NodeDecl*>& /*selected*/,
                                 CommandContext& /*ctx*/) override {
    start_scale_ = options_.distance_scale;
    if (!azimuths_.empty()) options_.azimuths_deg = azimuths_;
    if (!elevations_.empty()) options_.elevations_deg = elevations_;
    return std::nullopt;
  }

  void prepare(CommandContext& /*ctx*/) override {
    scene_renderer_ = &render::shared_renderer();
    impostor_renderer_ = &render::shared_impostor_renderer();
  }

  int check_node(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                 const fs::path& report_dir, CommandContext& ctx) override {
    impostor::ImpostorCheckResult results;
    impostor::ImpostorSubject subject;
    impostor::ColourBaseline baseline;
    render::Scene baseline_scene;
    Reference full;
    const int rc = guarded(node, report_dir, ctx, [&] {
      const InputArtifact out = input_artifact(recipe, built, node.name);
      const ArtifactFile* json = out.file("impostor.json");
      if (!json) return fail_node(node, report_dir, "the node wrote no impostor.json", ctx);
      subject = impostor::load_impostor_subject(json->path.parent_path(), "impostor");
      full = reference_of(recipe, built, node.needs.at(0), baseline_scene, baseline, ctx);

      if (ctx.cancelled()) throw Cancelled();
      StagedReportDir staged(ctx.fs, report_dir);
      const fs::path& dir = staged.path();
      const impostor::ImpostorImageSink sink = [&](const impostor::ImpostorViewCheck& c,
                                                   const image::Image& ref, const image::Image& test,
                                                   const image::Image& diff) {
        if (!keep_images(ctx)) return;
        image::write_png(ref, dir / ("full_" + c.view + ".png"));
        image::write_png(test, dir / ("impostor_" + c.view + ".png"));
        image::write_png(diff, dir / ("impostor_" + c.view + "_diff.png"));
      };
      if (pixel_threshold_opt_->count() == 0)
        options_.pixel_threshold = std::min(1.0, subject.info.pixel_error_px);
      std::optional<impostor::DistanceSearchResult> search;
      if (search_) {
        search = search_distance(node, full.scene, subject, baseline, ctx);
        results = search->at_proven;
        options_.distance_scale =
            search->proven_scale;  // for the report; the next node starts at start_scale_
      } else {
        results = impostor::check_impostor(*scene_renderer_, *impostor_renderer_, full.scene, subject,
                                           options_, baseline, sink);
      }
      write_json_report(dir / "impostorcheck.json",
                        json_report(node, subject.info, full, baseline, results, search ? &*search : nullptr),
                        ctx);
      if (search)
        std::fprintf(
            ctx.io.out,
            "sylva impostorcheck: node '%s' proven from %.1f m%s (x%.4f of the error model's %.1f m)\n",
            node.name.c_str(), search->proven_distance_m, search->below_lo ? " or nearer" : "",
            search->proven_scale, search->model_distance_m);
      if (search && search->proven_distance_m <= 0) {
        staged.commit();
        return fail_node(node, report_dir, "no distance up to 64 x the switch distance passes", ctx);
      }
      if (ctx.cancelled()) throw Cancelled();
      staged.commit();
      return kExitOk;
    });
    if (rc != kExitOk) return rc;
    return print_table(node, subject.info, full, baseline, results, report_dir, ctx.io);
  }

 private:
  // The full detail of what input `source` baked: a lod node's full.glb, with the chain's
  // coarsest level (which the impostor replaces) as the colour baseline; or a mesh node's one
  // .glb or .gltf. Throws std::runtime_error naming the input when its files are not as expected.
  static Reference reference_of(const Recipe& recipe, const RecipeBuild& built, const std::string& source,
                                render::Scene& baseline_scene, impostor::ColourBaseline& baseline,
                                CommandContext& ctx) {
    Reference full;
    const NodeDecl* src = recipe.find(source);
    if (src && src->stage && src->stage->info().name == "lod") {
      full.scene = lod_full_detail_scene(recipe, built, source, ctx);
      full.label = source + " (lod chain at epsilon 0)";
      const InputArtifact lod = input_artifact(recipe, built, source);
      const ArtifactFile* summary = lod.file("lod.json");
      if (!summary) throw std::runtime_error("input '" + source + "' has no lod.json");
      const std::string coarsest = lodchain::read_lod_chain(summary->path.string()).levels.back().file;
      const ArtifactFile* last = lod.file(coarsest);
      if (!last)
        throw std::runtime_error("input '" + source + "' lacks " + coarsest + ", which its lod.json lists");
      baseline_scene = render::load_gltf_scene(last->path);
      baseline.scene = &baseline_scene;
      baseline.label = coarsest;
    } else {
      const InputArtifact mesh = input_artifact(recipe, built, source);
      std::vector<const ArtifactFile*> files = mesh.files_with_suffix(".glb");
      for (const ArtifactFile* f : mesh.files_with_suffix(".gltf")) files.push_back(f);
      if (files.size() != 1)
        throw std::runtime_error("input '" + source + "' must hold exactly one .glb or .gltf file");
      full.scene = render::load_gltf_scene(files.front()->path);
      full.label = source + " (" + files.front()->name + ")";
    }
    full.triangles = full.scene.triangle_count();
    full.lines = full.scene.line_count();
    return full;
  }

  // --search-distance: the nearest multiple of the switch distance at which the check passes,
  // printing each step. The search starts at --distance-scale (billboards: far below the error
  // model's distance, where they are degenerate) and goes down to a 16th of it.
  impostor::DistanceSearchResult search_distance(const NodeDecl& node, const render::Scene& full,
                                                 const impostor::ImpostorSubject& subject,
                                                 const impostor::ColourBaseline& baseline,
                                                 CommandContext& ctx) {
    const impostor::DistanceStepSink step_sink = [&](const impostor::DistanceSearchStep& st) {
      if (ctx.cancelled()) throw Cancelled();
      std::fprintf(ctx.io.out, "  search %s: x%.4f = %.1f m %s%s\n", node.name.c_str(), st.scale,
                   st.distance_m, st.passed ? "passed" : "FAILED: ", st.passed ? "" : st.failure.c_str());
      std::fflush(ctx.io.out);
    };
    impostor::DistanceSearchOptions range;
    range.hi = start_scale_;
    range.lo = start_scale_ / 16;
    return impostor::find_proven_distance(*scene_renderer_, *impostor_renderer_, full, subject, options_,
                                          range, baseline, step_sink);
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

  int print_table(const NodeDecl& node, const impostor::ImpostorInfo& info, const Reference& full,
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
        full.label.c_str(), full.triangles, full.lines, 100 * options_.max_failing_fraction,
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

  nlohmann::json json_report(const NodeDecl& node, const impostor::ImpostorInfo& info, const Reference& full,
                             const impostor::ColourBaseline& baseline,
                             const impostor::ImpostorCheckResult& result,
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
    j["full_detail"] = {{"reference", full.label}, {"triangles", full.triangles}, {"lines", full.lines}};
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
    return j;
  }

  render::Renderer* scene_renderer_ = nullptr;  // prepare()
  render::ImpostorRenderer* impostor_renderer_ = nullptr;
  impostor::ImpostorCheckOptions options_;
  CLI::Option* pixel_threshold_opt_ = nullptr;
  std::vector<double> azimuths_, elevations_;
  bool search_ = false;
  double start_scale_ = 1;  // --distance-scale as given (a search reports each node at its own)
};

}  // namespace

std::unique_ptr<CliCommand> make_impostorcheck_command() { return std::make_unique<ImpostorcheckCommand>(); }

}  // namespace sylva
