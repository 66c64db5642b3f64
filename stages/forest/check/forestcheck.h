// `sylva lodcheck` on a forest: every view of the forest's camera set drawn twice, once with each
// tree at the LOD level its distance selects (libs/render/forest_view.h) and once with every tree
// at full detail, and judged as the tree lodcheck judges a level (libs/check/judge.h):
// over the forest's footprint (pixels either image covers, transparent background so alpha is
// coverage) a pixel fails when its coverage changes by more than delta, and a view passes when at
// most max_failing_fraction of the footprint fails and the mean coverage change is at most
// max_coverage_error. Primitives drawn are reported against the full detail's.
//
// The image may be smaller than the chain's H (full detail is slow): the levels are then chosen
// for that image, with switch distances scaled by height_px / H (a level's error is delta pixels
// of THIS image at its switch distance), so the check proves the same bound at its own resolution.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "libs/image/coverage.h"
#include "libs/image/image.h"
#include "libs/render/forest_view.h"

namespace sylva::forest {

struct ForestCheckOptions {
  int width_px = 480, height_px = 270;  // the check's image
  int msaa = 4;
  int supersample = 2;           // render at k x and average down (as the tree lodcheck)
  double pixel_threshold = 0.5;  // coverage change of a failing pixel (delta)
  double max_failing_fraction = 0.01;
  double max_coverage_error = 0.15;
};

struct ForestViewCheck {
  std::string view;
  std::size_t trees_drawn = 0;
  std::size_t lod_primitives = 0, full_primitives = 0;
  std::vector<std::size_t> per_level;  // trees at each level in the LOD view
  image::FootprintStats stats;         // the LOD view against the full-detail view
  bool passed = false;
  std::string failure;  // empty when passed
};

using ForestCheckSink = std::function<void(const ForestViewCheck&, const image::Image& full,
                                           const image::Image& lod, const image::Image& diff)>;

// `view` must have every species' full-detail model set. Throws render::RenderError.
std::vector<ForestViewCheck> check_forest(render::ForestView& view, render::Renderer& renderer,
                                          const std::vector<render::Camera>& cameras,
                                          const ForestCheckOptions& options,
                                          const ForestCheckSink& sink = {});

}  // namespace sylva::forest
