// The LOD error model (docs/lod-model.md) checked in image space for impostors (impostorcheck.h): renders
// from libs/render (the verifier's renderer for the full detail and the billboard cards, the reference
// impostor shader for the octahedral kinds), statistics and verdict from libs/check (judge.h), the
// coverage judged as lodcheck judges LOD levels, plus the colour of what both renders cover.
#include "stages/impostor/check/impostorcheck.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "libs/check/judge.h"
#include "libs/image/compare.h"
#include "libs/image/coverage.h"
#include "libs/image/resample.h"
#include "libs/impostor/error_model.h"
#include "libs/impostor/octahedral.h"
#include "libs/lodmodel/lod_model.h"
#include "libs/render/distance_camera.h"

namespace sylva::impostor {

namespace {

Vec3 view_direction(double az_deg, double el_deg) {
  const double a = az_deg * std::numbers::pi / 180, e = el_deg * std::numbers::pi / 180;
  return Vec3(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
}

}  // namespace

double nearest_frame_angle_deg(const ImpostorInfo& info, const Vec3& view) {
  double best = std::numbers::pi;
  auto consider = [&](const Vec3& d) {
    best = std::min(best, std::acos(std::clamp(view.normalized().dot(d), -1.0, 1.0)));
  };
  if (info.kind == Kind::kBillboards) {
    for (const Card& c : info.cards) consider(Vec3(c.dir[0], c.dir[1], c.dir[2]));
  } else {
    for (int j = 0; j < info.frames_per_side; ++j)
      for (int i = 0; i < info.frames_per_side; ++i)
        consider(frame_direction(i, j, info.frames_per_side, info.hemi));
  }
  return best * 180 / std::numbers::pi;
}

namespace {

// The views of a check: the cameras (elevations x azimuths at `distance`, cropped to the
// full-detail box's sphere plus a margin), their angles, and the render options at k x supersampling.
struct CheckViews {
  double distance = 0;
  int k = 1;
  render::RenderOptions ro;
  std::vector<render::Camera> cams;
  std::vector<std::pair<double, double>> angles;  // (azimuth, elevation), degrees
};

CheckViews check_views(const ImpostorInfo& info, const render::Bounds& bounds,
                       const ImpostorCheckOptions& o) {
  CheckViews v;
  v.distance = info.switch_distance_m * o.distance_scale;
  // The crop: the full-detail box's sphere seen from the nearest distance, plus a margin.
  const double px = lodmodel::pixel_size(info.camera, v.distance);
  const int crop = std::min(info.camera.height_px, int(std::ceil(2.4 * bounds.radius() / px)) + 8);
  // Supersampling: at least o.supersample, and enough that a render pixel is no larger than an
  // atlas texel, so the full detail is drawn at the resolution the atlas was baked at. Coarser,
  // its alpha-tested cards are sampled from mip levels whose alpha falls under the cutoff and
  // vanish, while the atlas (baked at texel scale) kept them: the check would compare the
  // impostor with a tree that lost its leaves to texture filtering, not with the tree.
  v.k = std::clamp(std::max(o.supersample, int(std::ceil(px / std::max(info.error.texel_m, 1e-9)))), 1, 8);
  v.ro.width = v.ro.height = crop * v.k;
  v.ro.msaa = o.msaa;
  v.ro.line_width_px = float(v.k);
  v.ro.background.a = 0;
  for (double el : o.elevations_deg)
    for (double az : o.azimuths_deg) {
      v.cams.push_back(render::camera_at_box_distance(bounds, v.distance, az, el, info.camera.fov_y_rad,
                                                      info.camera.height_px, crop));
      v.angles.push_back({az, el});
    }
  return v;
}

// The baseline (the level the impostor replaces; valid from its own switch distance on, so at
// the impostor's too) from the same cameras: its colour difference per view against `ref`, and
// its worst and mean into `result`. Empty without a baseline scene.
std::vector<double> baseline_colours(render::Renderer& scene_renderer, const ColourBaseline& baseline,
                                     const CheckViews& v, const std::vector<image::Image>& ref,
                                     const ImpostorCheckOptions& o, ImpostorCheckResult& result) {
  std::vector<double> colour;
  if (!baseline.scene) return colour;
  const std::vector<image::Image> btest = scene_renderer.render_views(*baseline.scene, v.cams, v.ro);
  double sum = 0, worst = 0;
  for (std::size_t i = 0; i < v.cams.size(); ++i) {
    const image::FootprintStats f = image::footprint_stats(
        image::downsample(ref[i], v.k), image::downsample(btest[i], v.k), o.pixel_threshold);
    colour.push_back(f.shade_mean_error);
    sum += f.shade_mean_error;
    worst = std::max(worst, f.shade_mean_error);
  }
  result.baseline_colour_max = worst;
  result.baseline_colour_mean = v.cams.empty() ? 0 : sum / double(v.cams.size());
  return colour;
}

// The impostor drawn from every view (billboards as cards by the scene renderer, the octahedral
// kinds by the reference impostor shader), and the primitives it draws.
std::vector<image::Image> render_subject(render::Renderer& scene_renderer,
                                         render::ImpostorRenderer& impostor_renderer,
                                         const ImpostorSubject& subject, const CheckViews& v,
                                         const ImpostorCheckOptions& o, std::size_t& primitives) {
  if (subject.info.kind == Kind::kBillboards) {
    primitives = subject.cards.triangle_count() + subject.cards.line_count();
    return scene_renderer.render_views(subject.cards, v.cams, v.ro);
  }
  render::ImpostorDrawOptions draw;
  draw.parallax_steps = o.parallax_steps;
  primitives = 2 * subject.octahedral.instances.size();
  return impostor_renderer.render_octahedral(subject.octahedral, v.cams, v.ro, draw);
}

// View i judged: coverage as lodcheck judges LOD levels, then the colour against its bound.
ImpostorViewCheck judge_view(const ImpostorSubject& subject, const CheckViews& v, std::size_t i,
                             const image::Image& r, const image::Image& t, const ImpostorCheckOptions& o,
                             const std::vector<double>& baseline_colour, std::size_t primitives) {
  check::CoverageThresholds thresholds;
  thresholds.pixel_threshold = o.pixel_threshold;
  thresholds.max_failing_fraction = o.max_failing_fraction;
  thresholds.max_coverage_error = o.max_coverage_error;
  thresholds.empty_fails = true;  // the distance search stops where no view covers a pixel
  const check::ViewJudgement j = check::judge_coverage(r, t, thresholds, "tree");
  const image::FootprintStats& f = j.stats;
  ImpostorViewCheck c;
  c.label = subject.label;
  c.view = v.cams[i].name;
  c.azimuth_deg = v.angles[i].first;
  c.elevation_deg = v.angles[i].second;
  c.frame_angle_deg = nearest_frame_angle_deg(subject.info, view_direction(c.azimuth_deg, c.elevation_deg));
  c.distance = v.distance;
  c.footprint_pixels = f.footprint_pixels;
  c.coverage_failing_fraction = f.failing_fraction;
  c.coverage_mean_error = f.coverage_mean_error;
  c.coverage_bias = f.coverage_bias;
  c.colour_mean_error = f.colour_mean_error;
  c.shade_mean_error = f.shade_mean_error;
  c.primitives = primitives;
  c.failure = j.failure;
  c.colour_bound = check::colour_bound(o.max_colour_error, o.colour_ratio,
                                       baseline_colour.empty() ? -1 : baseline_colour[i]);
  c.baseline_colour = baseline_colour.empty() ? -1 : baseline_colour[i];
  if (c.failure.empty()) c.failure = check::colour_failure(c.shade_mean_error, c.colour_bound);
  c.passed = c.failure.empty();
  return c;
}

}  // namespace

ImpostorCheckResult check_impostor(render::Renderer& scene_renderer,
                                   render::ImpostorRenderer& impostor_renderer, const render::Scene& full,
                                   const ImpostorSubject& subject, const ImpostorCheckOptions& o,
                                   const ColourBaseline& baseline, const ImpostorImageSink& sink) {
  const CheckViews v = check_views(subject.info, full.bounds(), o);
  const std::vector<image::Image> ref = scene_renderer.render_views(full, v.cams, v.ro);
  ImpostorCheckResult result;
  const std::vector<double> baseline_colour = baseline_colours(scene_renderer, baseline, v, ref, o, result);
  std::size_t primitives = 0;
  const std::vector<image::Image> test =
      render_subject(scene_renderer, impostor_renderer, subject, v, o, primitives);

  image::CompareOptions heat;
  heat.pixel_threshold = o.pixel_threshold;
  for (std::size_t i = 0; i < v.cams.size(); ++i) {
    const image::Image r = image::downsample(ref[i], v.k), t = image::downsample(test[i], v.k);
    ImpostorViewCheck c = judge_view(subject, v, i, r, t, o, baseline_colour, primitives);
    if (sink) sink(c, r, t, image::diff_heatmap(r, t, heat));
    result.colour_mean += c.shade_mean_error / double(v.cams.size());
    result.views.push_back(std::move(c));
  }
  if (!baseline_colour.empty())
    result.failure = check::mean_colour_failure(result.colour_mean, result.baseline_colour_mean,
                                                o.colour_tolerance, baseline.label);
  return result;
}

DistanceSearchResult find_proven_distance(render::Renderer& scene_renderer,
                                          render::ImpostorRenderer& impostor_renderer,
                                          const render::Scene& full, const ImpostorSubject& subject,
                                          ImpostorCheckOptions o, const DistanceSearchOptions& search,
                                          const ColourBaseline& baseline, const DistanceStepSink& step_sink) {
  if (!(search.hi > 0 && search.lo > 0 && search.lo <= search.hi && search.tolerance > 0))
    throw std::invalid_argument("distance search: need 0 < lo <= hi and tolerance > 0");
  DistanceSearchResult out;
  out.model_distance_m = subject.info.switch_distance_m;
  bool vanished = false;  // every view's footprint was empty: farther can only be emptier
  auto run = [&](double scale) {
    o.distance_scale = scale;
    ImpostorCheckResult r = check_impostor(scene_renderer, impostor_renderer, full, subject, o, baseline);
    DistanceSearchStep step;
    step.scale = scale;
    step.distance_m = out.model_distance_m * scale;
    step.passed = r.passed();
    for (const ImpostorViewCheck& v : r.views)
      if (!v.passed && step.failure.empty()) step.failure = v.view + ": " + v.failure;
    if (step.failure.empty()) step.failure = r.failure;
    vanished =
        !r.views.empty() && std::all_of(r.views.begin(), r.views.end(),
                                        [](const ImpostorViewCheck& v) { return v.footprint_pixels == 0; });
    out.steps.push_back(step);
    if (step_sink) step_sink(step);
    return r;
  };
  double pass = search.hi, fail = 0;
  ImpostorCheckResult at_pass = run(pass);
  while (!at_pass.passed()) {
    fail = pass;
    if (pass >= 64 * search.hi || vanished) return out;  // nothing passed
    pass *= 2;
    at_pass = run(pass);
  }
  if (fail == 0) {
    ImpostorCheckResult at_lo = run(search.lo);
    if (at_lo.passed()) {
      out.below_lo = true;
      pass = search.lo;
      at_pass = std::move(at_lo);
    } else {
      fail = search.lo;
    }
  }
  while (fail > 0 && pass / fail > 1 + search.tolerance) {
    const double mid = std::sqrt(pass * fail);
    ImpostorCheckResult r = run(mid);
    if (r.passed()) {
      pass = mid;
      at_pass = std::move(r);
    } else {
      fail = mid;
    }
  }
  out.proven_scale = pass;
  out.proven_distance_m = out.model_distance_m * pass;
  out.at_proven = std::move(at_pass);
  return out;
}

bool ImpostorCheckResult::passed() const {
  if (!failure.empty()) return false;
  for (const auto& v : views)
    if (!v.passed) return false;
  return true;
}

}  // namespace sylva::impostor
