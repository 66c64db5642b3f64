// The forest lodcheck (see forestcheck.h). The footprint statistics are the tree lodcheck's
// (stages/lod/check/lodcheck.cpp, computed the same way: no stage includes another's files).
#include "stages/forest/check/forestcheck.h"

#include <cmath>
#include <cstdio>

#include "libs/image/compare.h"
#include "libs/image/resample.h"

namespace sylva::forest {

namespace {

void footprint_stats(const image::Image& ref, const image::Image& test, double threshold,
                     ForestViewCheck& c) {
  const auto& rb = ref.bytes();
  const auto& tb = test.bytes();
  double sum = 0, bias = 0, colour = 0;
  std::size_t failing = 0;
  for (std::size_t p = 0; p + 3 < rb.size() && p + 3 < tb.size(); p += 4) {
    if (rb[p + 3] == 0 && tb[p + 3] == 0) continue;
    ++c.footprint_pixels;
    const double d = (int(tb[p + 3]) - int(rb[p + 3])) / 255.0;
    sum += std::abs(d);
    bias += d;
    failing += std::abs(d) > threshold ? 1 : 0;
    for (int ch = 0; ch < 3; ++ch)
      colour += std::abs(int(rb[p + std::size_t(ch)]) - int(tb[p + std::size_t(ch)])) / 255.0;
  }
  if (c.footprint_pixels == 0) return;
  const double n = double(c.footprint_pixels);
  c.coverage_failing_fraction = double(failing) / n;
  c.coverage_mean_error = sum / n;
  c.coverage_bias = bias / n;
  c.colour_mean_error = colour / (3 * n);
}

}  // namespace

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
    footprint_stats(full_img, lod_img, o.pixel_threshold, c);
    char buf[256];
    if (c.coverage_failing_fraction > o.max_failing_fraction) {
      std::snprintf(
          buf, sizeof buf,
          "coverage of %.2f%% of the forest's %zu pixels changed by more than %.3g (allowed %.2f%%)",
          100 * c.coverage_failing_fraction, c.footprint_pixels, o.pixel_threshold,
          100 * o.max_failing_fraction);
      c.failure = buf;
    } else if (c.coverage_mean_error > o.max_coverage_error) {
      std::snprintf(buf, sizeof buf,
                    "mean coverage change over the forest's %zu pixels is %.4f (allowed %.4f)",
                    c.footprint_pixels, c.coverage_mean_error, o.max_coverage_error);
      c.failure = buf;
    }
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
