// The forest lodcheck (see forestcheck.h), judged as the tree lodcheck judges a level
// (libs/check/judge.h: the same footprint statistics, bounds and sentences).
#include "stages/forest/check/forestcheck.h"

#include <algorithm>

#include "libs/check/judge.h"
#include "libs/image/compare.h"
#include "libs/image/resample.h"

namespace sylva::forest {

std::vector<ForestViewCheck> check_forest(render::ForestView& view, render::Renderer& renderer,
                                          const std::vector<render::Camera>& cameras,
                                          const ForestCheckOptions& o, const ForestCheckSink& sink) {
  const int k = std::max(1, o.supersample);
  render::RenderOptions ro;
  ro.width = o.width_px * k;
  ro.height = o.height_px * k;
  ro.msaa = o.msaa;
  ro.line_width_px = float(k);
  ro.background.a = 0;
  check::CoverageThresholds thresholds;
  thresholds.pixel_threshold = o.pixel_threshold;
  thresholds.max_failing_fraction = o.max_failing_fraction;
  thresholds.max_coverage_error = o.max_coverage_error;
  std::vector<ForestViewCheck> out;
  for (const render::Camera& cam : cameras) {
    // Levels chosen for delta pixels of this image: delta' = delta H / height_px at the chain's H.
    // Judged on the trees' coverage: the ground (the same in both views) would cover every pixel.
    render::ForestViewOptions lod;
    lod.ground = false;
    const Species& s0 = view.forest().species.at(0);
    lod.pixel_error_px = s0.pixel_error_px * double(s0.height_px) / double(o.height_px);
    render::ForestViewOptions full;
    full.full_detail = true;
    full.ground = false;
    std::vector<render::ForestViewStats> ls, fs;
    const std::span<const render::Camera> one(&cam, 1);
    image::Image lod_img = view.render(renderer, one, ro, lod, &ls).front();
    image::Image full_img = view.render(renderer, one, ro, full, &fs).front();
    if (k > 1) {
      lod_img = image::downsample(lod_img, k);
      full_img = image::downsample(full_img, k);
    }
    ForestViewCheck c;
    c.view = cam.name;
    c.trees_drawn = ls.front().trees_drawn;
    c.lod_primitives = ls.front().primitives;
    c.full_primitives = fs.front().primitives;
    c.per_level = ls.front().per_level;
    const check::ViewJudgement j = check::judge_coverage(full_img, lod_img, thresholds, "forest");
    c.stats = j.stats;
    c.failure = j.failure;
    c.passed = c.failure.empty();
    if (sink) {
      image::CompareOptions heat;
      heat.pixel_threshold = o.pixel_threshold;
      sink(c, full_img, lod_img, image::diff_heatmap(full_img, lod_img, heat));
    }
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace sylva::forest
