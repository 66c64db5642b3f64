// `sylva render`: a straight sequence of named passes — camera set, views, output plan, scene,
// renderer, render, write — each failing with its own one-line message and exit code. Cheap
// checks (options, camera set, the asset) come before creating the EGL context.
#include "app/render_command.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "app/gfx_module.h"
#include "libs/image/image_io.h"
#include "libs/render/camera.h"
#include "libs/render/forest_view.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// Library errors already read "path: error: reason"; everything else gets the usual prefix.
void print_error(std::FILE* err, const std::string& what) {
  if (what.find(": error: ") != std::string::npos)
    std::fprintf(err, "%s\n", what.c_str());
  else
    std::fprintf(err, "error: %s\n", what.c_str());
}

double seconds_since(const Clock& clock, double t) { return clock.now_seconds() - t; }

bool has_png_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png";
}

class RenderCommand final : public CliCommand {
 public:
  CLI::App* add_to(CLI::App& app) override {
    auto* sub = app.add_subcommand("render", gfx_command_summary("render"));
    sub->add_option("file", file_, "the .glb or .gltf file, or a forest's instances.json")->required();
    sub->add_option(
        "--camera", camera_,
        "camera set (default: configs/cameras/default.yaml; a forest's own cameras.yaml for a forest)");
    sub->add_option("--pixel-error", pixel_error_,
                    "forest: the view's pixel error delta (default: each species' chain delta)")
        ->check(CLI::Range(0.01, 1000.0));

    sub->add_option("--view", views_,
                    "render only this view (repeatable; default: every view, or the first for -o FILE.png)")
        ->allow_extra_args(false);
    sub->add_option("-o,--output", output_, "a .png file (one view) or a directory (one <view>.png per view)")
        ->required();
    return sub;
  }

  int run(CommandContext& ctx) override {
    const CliIo& io = ctx.io;
    // A forest (instances.json) is drawn with its LOD levels per tree (libs/render/forest_view.h)
    // and, unless --camera says otherwise, its own camera set.
    const bool forest = fs::path(file_).filename() == "instances.json";
    if (forest && camera_ == kDefaultCameras)
      camera_ = (fs::path(file_).parent_path() / "cameras.yaml").string();
    // 1. The camera set.
    render::CameraSet set;
    try {
      set = render::load_camera_set(camera_);
    } catch (const render::CameraSetError& e) {
      std::fprintf(io.err, "%s\n", e.what());
      if (!ctx.fs.stat(camera_) && camera_ == kDefaultCameras)
        std::fprintf(io.err, "(run sylva from the repository root, or name a camera set with --camera)\n");
      return kExitUsage;
    }

    // 2. The views, 3. one file or a directory.
    bool single = false;
    if (const int rc = choose_views(ctx, set, single); rc != kExitOk) return rc;

    // 4. The asset, 5. the renderer, 6. the pictures.
    const double start = ctx.clock.now_seconds();
    std::vector<render::RenderedView> images;
    try {
      const int rc = forest ? render_forest(ctx, set, start, images) : render_asset(ctx, set, images);
      if (rc != kExitOk) return rc;
      if (cancelled(io)) return report_interrupted(io, "sylva render");
    } catch (const std::exception& e) {  // SceneLoadError, RenderUnavailableError, RenderError: one line each
      print_error(io.err, e.what());
      return kExitBuildFailed;
    }

    // 7. Write.
    if (const int rc = write_images(ctx, images, single); rc != kExitOk) return rc;
    const double seconds = seconds_since(ctx.clock, start);
    const std::string aa = "MSAA " + std::to_string(set.msaa) + "x" +
                           (set.supersample > 1 ? ", supersampled " + std::to_string(set.supersample) + "x" +
                                                      std::to_string(set.supersample)
                                                : std::string());
    std::fprintf(io.err, "sylva: rendered %zu view%s of %s at %dx%d (%s) in %.2f s\n", images.size(),
                 images.size() == 1 ? "" : "s", file_.c_str(), set.width, set.height, aa.c_str(), seconds);
    return kExitOk;
  }

 private:
  // The views: --view names, in the order given (unknown names are usage errors), else every
  // view, or the first for -o FILE.png; `single`: -o names one image. Leaves them in set.views.
  int choose_views(CommandContext& ctx, render::CameraSet& set, bool& single) const {
    const CliIo& io = ctx.io;
    std::vector<render::CameraView> chosen;
    for (const auto& name : views_) {
      auto it =
          std::find_if(set.views.begin(), set.views.end(), [&](const auto& v) { return v.name == name; });
      if (it == set.views.end()) {
        std::string names;
        for (const auto& v : set.views) names += (names.empty() ? "" : ", ") + v.name;
        std::fprintf(io.err, "error: no view '%s' in %s (its views: %s)\n", name.c_str(), camera_.c_str(),
                     names.c_str());
        return kExitUsage;
      }
      if (std::none_of(chosen.begin(), chosen.end(), [&](const auto& v) { return v.name == name; }))
        chosen.push_back(*it);
    }
    const auto out_stat = ctx.fs.stat(output_);
    single = has_png_extension(output_) && !(out_stat && out_stat->is_dir);
    if (chosen.empty()) {
      if (single)
        chosen.push_back(set.views.front());
      else
        chosen = set.views;
    }
    if (single && chosen.size() > 1) {
      std::fprintf(io.err,
                   "error: -o %s is one image but %zu views were chosen; give -o a directory for several\n",
                   output_.c_str(), chosen.size());
      return kExitUsage;
    }
    set.views = chosen;
    return kExitOk;
  }

  // A forest: its levels and impostor maps uploaded first, then each view with what it drew.
  // `start`: when loading began (clock seconds).
  int render_forest(CommandContext& ctx, const render::CameraSet& set, double start,
                    std::vector<render::RenderedView>& images) const {
    const CliIo& io = ctx.io;
    render::ForestView fv = render::ForestView::load(file_);
    const double load_s = seconds_since(ctx.clock, start);
    auto renderer = render::Renderer::create_headless();
    const std::vector<render::Camera> cams = render::forest_cameras(set, fv.bounds());
    render::ForestViewOptions fo;
    fo.pixel_error_px = pixel_error_;
    // Every level and impostor map the views draw is uploaded before the first view (the
    // loading step), so each view's time below is its drawing.
    const double upload_start = ctx.clock.now_seconds();
    fv.prepare(*renderer, cams, render::options_for(set), fo);
    std::fprintf(io.err, "sylva: forest loaded in %.2f s, uploaded in %.2f s\n", load_s,
                 seconds_since(ctx.clock, upload_start));
    // One view at a time: Ctrl-C or SIGTERM stops between views, before anything is written.
    for (std::size_t i = 0; i < cams.size(); ++i) {
      if (cancelled(io)) return report_interrupted(io, "sylva render");
      const double view_start = ctx.clock.now_seconds();
      std::vector<render::ForestViewStats> stats;
      std::vector<image::Image> imgs = fv.render(*renderer, std::span<const render::Camera>(&cams[i], 1),
                                                 render::options_for(set), fo, &stats);
      std::fprintf(io.err,
                   "sylva: view %s: %zu of %zu trees drawn (%zu as impostors), %zu primitives, %.2f s\n",
                   cams[i].name.c_str(), stats[0].trees_drawn, stats[0].trees, stats[0].impostors,
                   stats[0].primitives, seconds_since(ctx.clock, view_start));
      print_forest_view_levels(io, fv, stats[0]);
      images.push_back({cams[i], std::move(imgs[0])});
    }
    return kExitOk;
  }

  // Per species: trees at each level (level index: count), impostors by parallax steps.
  static void print_forest_view_levels(const CliIo& io, const render::ForestView& fv,
                                       const render::ForestViewStats& stats) {
    for (std::size_t s = 0; s < stats.species_trees.size(); ++s) {
      std::string line;
      for (std::size_t l = 0; l < stats.species_trees[s].size(); ++l)
        if (stats.species_trees[s][l] > 0)
          line += " L" + std::to_string(l) + ": " + std::to_string(stats.species_trees[s][l]);
      if (!line.empty())
        std::fprintf(io.err, "sylva:   %s:%s\n", fv.forest().species[s].name.c_str(), line.c_str());
    }
    if (!stats.impostor_steps.empty()) {
      std::string line;
      for (const auto& [steps, n] : stats.impostor_steps)
        line += " " + std::to_string(n) + " with " + std::to_string(steps) + " steps";
      std::fprintf(io.err, "sylva:   impostors:%s\n", line.c_str());
    }
  }

  // A glTF asset: its warnings, then one view at a time.
  int render_asset(CommandContext& ctx, const render::CameraSet& set,
                   std::vector<render::RenderedView>& images) const {
    const CliIo& io = ctx.io;
    const render::Scene scene = render::load_gltf_scene(file_);
    for (const auto& w : scene.warnings) std::fprintf(io.err, "%s\n", w.c_str());
    auto renderer = render::Renderer::create_headless();
    for (const auto& view : set.views) {
      if (cancelled(io)) return report_interrupted(io, "sylva render");
      render::CameraSet one = set;
      one.views = {view};
      for (auto& v : render::render_camera_set(*renderer, scene, one)) images.push_back(std::move(v));
    }
    return kExitOk;
  }

  // -o FILE.png, or one <view>.png per view in the directory -o (made when missing).
  int write_images(CommandContext& ctx, const std::vector<render::RenderedView>& images, bool single) const {
    const CliIo& io = ctx.io;
    try {
      if (!single) {
        std::string why;
        if (!ctx.fs.make_dirs(output_, &why)) {
          std::fprintf(io.err, "%s: error: cannot create the directory: %s\n", output_.c_str(), why.c_str());
          return kExitBuildFailed;
        }
      }
      for (const auto& v : images) {
        const fs::path path = single ? fs::path(output_) : fs::path(output_) / (v.camera.name + ".png");
        image::write_png(v.image, path);
        std::fprintf(io.out, "%s\n", path.c_str());
      }
    } catch (const image::ImageError& e) {
      print_error(io.err, e.what());
      return kExitBuildFailed;
    }
    return kExitOk;
  }

  static constexpr const char* kDefaultCameras = "configs/cameras/default.yaml";
  std::string file_;
  std::string camera_ = kDefaultCameras;
  std::vector<std::string> views_;
  std::string output_;
  double pixel_error_ = 0;
};

}  // namespace

std::unique_ptr<CliCommand> make_render_command() { return std::make_unique<RenderCommand>(); }

}  // namespace sylva
