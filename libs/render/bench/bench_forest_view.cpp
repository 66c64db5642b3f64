// Forest-view benchmark (docs/performance.md "Forest"): one forest artifact's views at the camera
// set's size, each phase timed in CPU seconds of the whole process (llvmpipe's threads included)
// and of the calling thread, with the trees and primitives drawn per species and level.
//   bench_forest_view out/forest_celba/forest/instances.json [--view NAME]... [--msaa N]
//     [--supersample K] [--width W --height H] [--exact-impostors 1] [--judge-parallax 1] [--out DIR]
//     [--repeat N] [--hidden-discard 0|1] [--prepare 0|1] [--full SPECIES=FULL.glb]...
// --exact-impostors 1 draws every impostor with the reference shader's 16 parallax steps (the
// exact view the parallax table is judged against); --judge-parallax 1 also renders that exact
// view and judges the parallax table's view against it (forest lodcheck's judgement). --repeat N
// renders each view N times in a row ("render again"): a frame of a walk or flight after the
// first, when the renderer still holds the levels' buffers, the impostor maps and the target.
// --hidden-discard 0 marches the impostor fragments the meshes hide (RenderOptions::
// impostor_hidden_discard false: the same pixels, for comparisons). The chosen views' levels and
// impostor maps are uploaded first ("upload", ForestView::prepare, as `sylva render` and verify
// do); --prepare 0 leaves each upload to the first view that draws it (its "render" then
// includes it). --full SPECIES=FILE (every species: each lod node's full.glb) also counts what
// each view would draw with every tree at full detail (the same culling, no LOD; counted, not
// drawn) and prints the LOD view's primitive reduction, the figure Zhang et al. report.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/check/judge.h"
#include "libs/image/image_io.h"
#include "libs/render/camera.h"
#include "libs/render/forest_view.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/rasteriser_threads.h"

namespace {

double cpu(int who) {
  rusage r{};
  getrusage(who, &r);
  return double(r.ru_utime.tv_sec) + double(r.ru_utime.tv_usec) * 1e-6 + double(r.ru_stime.tv_sec) +
         double(r.ru_stime.tv_usec) * 1e-6;
}

struct Lap {
  double c = cpu(RUSAGE_SELF), t = cpu(RUSAGE_THREAD),
         w = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  void print(const char* what) {
    const Lap now;
    std::printf("  %-12s cpu %7.2f s  calling thread %7.2f s  wall %7.2f s\n", what, now.c - c, now.t - t,
                now.w - w);
    *this = now;
  }
};

// The command line (the flags above; a flag takes one value).
struct Args {
  std::filesystem::path file;
  std::vector<std::string> views;
  int msaa = -1, width = -1, height = -1, supersample = -1, repeat = 1, hidden_discard = -1;
  bool prepare = true;
  bool exact = false;  // every impostor with the reference shader's 16 steps, not the parallax table
  bool judge = false;  // judge the parallax table's view against the exact one
  std::string out;
  std::vector<std::string> full;  // SPECIES=FILE
};

Args parse_args(int argc, char** argv) {
  Args a;
  a.file = argv[1];
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--full")) a.full.push_back(argv[i + 1]);
    if (!std::strcmp(argv[i], "--view")) a.views.push_back(argv[i + 1]);
    if (!std::strcmp(argv[i], "--msaa")) a.msaa = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--out")) a.out = argv[i + 1];
    if (!std::strcmp(argv[i], "--width")) a.width = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--supersample")) a.supersample = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--exact-impostors")) a.exact = std::string(argv[i + 1]) == "1";
    if (!std::strcmp(argv[i], "--judge-parallax")) a.judge = std::string(argv[i + 1]) == "1";
    if (!std::strcmp(argv[i], "--height")) a.height = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--repeat")) a.repeat = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--hidden-discard")) a.hidden_discard = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--prepare")) a.prepare = std::string(argv[i + 1]) != "0";
  }
  return a;
}

// --full SPECIES=FILE: the full-detail models. 0, or the exit code after printing why not.
int set_full_detail(sylva::render::ForestView& fv, const std::vector<std::string>& full) {
  for (const std::string& f : full) {
    const std::size_t eq = f.find('=');
    const auto& species = fv.forest().species;
    const auto it = std::find_if(species.begin(), species.end(), [&](const auto& sp) {
      return eq != std::string::npos && sp.name == f.substr(0, eq);
    });
    if (it == species.end()) {
      std::fprintf(stderr, "--full %s: error: expected SPECIES=FILE with a species of the forest\n",
                   f.c_str());
      return 2;
    }
    try {
      fv.set_full_detail(std::size_t(it - species.begin()), sylva::render::load_gltf_scene(f.substr(eq + 1)));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "--full %s: %s\n", f.c_str(), e.what());
      return 1;
    }
  }
  return 0;
}

// As `sylva lodcheck` judges a forest view: trees only (no ground), transparent background
// (alpha = coverage), the exact view (16 steps everywhere) as the reference.
void judge_parallax(const sylva::render::ForestView& fv, sylva::render::Renderer& renderer,
                    const sylva::render::Camera& c, const sylva::render::RenderOptions& options) {
  using namespace sylva;
  render::ForestViewOptions trees;
  trees.ground = false;
  render::RenderOptions ro = options;
  ro.background.a = 0;
  render::ForestViewStats unused;
  render::Scene fast = fv.view_scene(c, float(options.width) / float(options.height), trees, unused);
  render::Scene ref = fast;
  for (render::ImpostorSet& is : ref.impostors) is.parallax_steps = render::ImpostorSet{}.parallax_steps;
  const image::Image a = renderer.render(ref, c, ro), b = renderer.render(fast, c, ro);
  const check::ViewJudgement j = check::judge_coverage(a, b, check::CoverageThresholds{}, "forest");
  std::printf(
      "  parallax table vs 16 steps: footprint %zu px, fail %.3f %%, cov_mean %.4f, cov_bias %+.4f, "
      "colour %.4f: %s\n",
      j.stats.footprint_pixels, 100 * j.stats.failing_fraction, j.stats.coverage_mean_error,
      j.stats.coverage_bias, j.stats.shade_mean_error, j.failure.empty() ? "passed" : j.failure.c_str());
}

// What the view drew: trees, impostors and primitives, the full-detail comparison (--full), the
// impostors by parallax steps, and per species the trees and primitives at each level.
void print_view_stats(const sylva::render::ForestView& fv, const sylva::render::Camera& c,
                      const sylva::render::RenderOptions& options, const sylva::render::ForestViewStats& st,
                      bool full) {
  using namespace sylva;
  std::printf("  trees %zu of %zu, impostors %zu, primitives %zu\n", st.trees_drawn, st.trees, st.impostors,
              st.primitives);
  if (full) {
    render::ForestViewOptions every_tree_full;
    every_tree_full.full_detail = true;
    render::ForestViewStats fs;
    (void)fv.view_scene(c, float(options.width) / float(options.height), every_tree_full, fs);
    const double drawn = 100.0 * double(st.primitives) / double(fs.primitives);
    std::printf("  full detail: trees %zu, primitives %zu; the LOD view draws %.3g %% of them (-%.6g %%)\n",
                fs.trees_drawn, fs.primitives, drawn, 100.0 - drawn);
  }
  std::printf("  impostors by parallax steps:");
  for (const auto& [steps, n] : st.impostor_steps) std::printf(" %d: %zu", steps, n);
  std::printf("\n");
  for (std::size_t s = 0; s < st.species_trees.size(); ++s) {
    std::printf("  %-12s", fv.forest().species[s].name.c_str());
    for (std::size_t l = 0; l < st.species_trees[s].size(); ++l)
      std::printf(" L%zu %4zu/%9zu", l, st.species_trees[s][l], st.species_primitives[s][l]);
    std::printf("\n");
  }
}

// One view: its scene, its render (and --repeat renders), the PNG (--out), the judgement
// (--judge-parallax) and what it drew.
void bench_view(const sylva::render::ForestView& fv, sylva::render::Renderer& renderer,
                const sylva::render::Camera& c, const sylva::render::RenderOptions& options, const Args& a,
                Lap& lap) {
  using namespace sylva;
  std::printf("view %s (%dx%d, MSAA %d, supersample %d)\n", c.name.c_str(), options.width, options.height,
              options.msaa, options.supersample);
  render::ForestViewStats st;
  render::Scene scene = fv.view_scene(c, float(options.width) / float(options.height), {}, st);
  if (a.exact)
    for (render::ImpostorSet& is : scene.impostors) is.parallax_steps = render::ImpostorSet{}.parallax_steps;
  lap.print("scene");
  const image::Image img = renderer.render(scene, c, options);
  lap.print("render");
  for (int r = 1; r < a.repeat; ++r) {
    (void)renderer.render(scene, c, options);
    lap.print("render again");
  }
  if (!a.out.empty()) {
    image::write_png(img, std::filesystem::path(a.out) / (c.name + ".png"));
    lap.print("png");
  }
  if (a.judge) {
    judge_parallax(fv, renderer, c, options);
    lap.print("judge");
  }
  print_view_stats(fv, c, options, st, !a.full.empty());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sylva;
  render::set_default_rasteriser_threads();  // as sylva does (docs/renderer.md "Rasteriser threads")
  if (argc < 2) {
    std::fprintf(
        stderr,
        "usage: %s instances.json [--view NAME]... [--msaa N] [--supersample K] [--width W --height H]\n"
        "  [--exact-impostors 1] [--judge-parallax 1] [--out DIR] [--repeat N] [--hidden-discard 0|1]\n"
        "  [--prepare 0|1] [--full SPECIES=FULL.glb]...\n",
        argv[0]);
    return 2;
  }
  const Args a = parse_args(argc, argv);
  if (!a.out.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (ec) {
      std::fprintf(stderr, "%s: error: cannot create the directory: %s\n", a.out.c_str(),
                   ec.message().c_str());
      return 1;
    }
  }
  Lap lap;
  render::ForestView fv = render::ForestView::load(a.file);
  if (const int rc = set_full_detail(fv, a.full); rc != 0) return rc;
  lap.print("load");
  render::CameraSet set = render::load_camera_set(a.file.parent_path() / "cameras.yaml");
  auto renderer = render::Renderer::create_headless();
  lap.print("context");
  render::RenderOptions options = render::options_for(set);
  if (a.msaa > 0) options.msaa = a.msaa;
  if (a.width > 0) options.width = a.width;
  if (a.supersample > 0) options.supersample = a.supersample;
  if (a.height > 0) options.height = a.height;
  if (a.hidden_discard >= 0) options.impostor_hidden_discard = a.hidden_discard == 1;
  std::vector<render::Camera> cams = render::forest_cameras(set, fv.bounds());
  if (!a.views.empty())
    std::erase_if(cams, [&](const render::Camera& c) {
      return std::find(a.views.begin(), a.views.end(), c.name) == a.views.end();
    });
  if (a.prepare) {
    fv.prepare(*renderer, cams, options);
    lap.print("upload");
  }
  for (const render::Camera& c : cams) bench_view(fv, *renderer, c, options, a, lap);
  return 0;
}
