// Zhang et al. 2017 §3 (delta, epsilon, s(d)), checked in image space: the renders come from
// libs/render (the verifier's renderer), the verdict from judge.h (coverage over the tree's
// footprint, since a distant tree is a few percent of the frame), the colour numbers and the
// heat-map from libs/image (OpenImageIO).
#include "libs/check/view_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <utility>

#include "libs/image/resample.h"
#include "libs/render/distance_camera.h"

namespace sylva::check {

namespace {

// Spare pixels around the full detail's projected box in a cropped window: a level's geometry
// lies within epsilon (delta px) of the full detail's, and lines are a pixel wide.
constexpr double kCropMarginPx = 8;

std::string view_name(double azimuth_deg) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "az%g", azimuth_deg);
  return buf;
}

std::size_t primitive_count(const render::Scene& s) { return s.triangle_count() + s.line_count(); }

// The side (px) of the centred square window of an H x H image from `cam` that holds the box
// `b` with `margin_px` to spare: the largest offset of a projected corner from the image centre
// (the box's projection lies in their hull). Same parity as H, so the window's pixels are
// exactly pixels of the full frame; H when a corner is not in front of the eye.
int crop_window(const render::Bounds& b, const render::Camera& cam, int height_px, double margin_px) {
  const render::Mat4 view = cam.view_matrix();
  const double t = 1.0 / std::tan(cam.fov_y_deg * std::numbers::pi / 360);
  double reach = 0;
  for (int c = 0; c < 8; ++c) {
    const render::Vec3 p((c & 1) ? b.max.x() : b.min.x(), (c & 2) ? b.max.y() : b.min.y(),
                         (c & 4) ? b.max.z() : b.min.z());
    const Eigen::Vector4f e = view * p.homogeneous();
    if (!(-e.z() > cam.z_near)) return height_px;
    reach = std::max({reach, std::abs(e.x()) * t / -e.z(), std::abs(e.y()) * t / -e.z()});
  }
  int w = 2 * static_cast<int>(std::ceil(reach * height_px / 2 + margin_px));
  if (w % 2 != height_px % 2) ++w;
  return std::min(w, height_px);
}

// `cam` narrowed to the centred window of w of its H pixels: the same eye and pixel size.
render::Camera cropped(render::Camera cam, int w, int height_px) {
  const double half = std::atan(std::tan(cam.fov_y_deg * std::numbers::pi / 360) * w / height_px);
  cam.fov_y_deg = static_cast<float>(2 * half * 180 / std::numbers::pi);
  return cam;
}

}  // namespace

CoverageThresholds ViewCheckOptions::thresholds() const {
  CoverageThresholds t;
  t.pixel_threshold = pixel_threshold;
  t.max_failing_fraction = max_failing_fraction;
  t.max_coverage_error = max_coverage_error;
  return t;
}

render::Camera check_camera(const render::Bounds& full_bounds, double distance, double azimuth_deg,
                            double elevation_deg, double fov_y_rad) {
  render::Camera cam =
      render::camera_at_box_distance(full_bounds, distance, azimuth_deg, elevation_deg, fov_y_rad);
  cam.name = view_name(azimuth_deg);  // one elevation per run: views are named by azimuth
  return cam;
}

ReferenceViews::ReferenceViews(render::Renderer& renderer, const render::Scene& full,
                               const lodmodel::Camera& camera, double distance,
                               const ViewCheckOptions& options)
    : renderer_(&renderer), options_(options), distance_(distance) {
  // The views' cameras, cropped to the centred window that holds the tree (the same for every
  // view and for every subject at this distance, so the images compare pixel for pixel; outside
  // it both images are empty). A far level is a small window.
  const int frame = camera.height_px;
  const render::Bounds bounds = full.bounds();
  for (double az : options.azimuths_deg) {
    cameras_.push_back(check_camera(bounds, distance, az, options.elevation_deg, camera.fov_y_rad));
    window_ =
        std::max(window_, options.crop ? crop_window(bounds, cameras_.back(), frame, kCropMarginPx) : frame);
  }
  for (auto& c : cameras_) c = cropped(c, window_, frame);
  images_ = render(full);
}

std::vector<image::Image> ReferenceViews::render(const render::Scene& subject) const {
  // Renders at k x the window, box-averaged down to it (header: supersampling).
  const int k = std::max(1, options_.supersample);
  render::RenderOptions ro;
  ro.width = ro.height = window_ * k;
  ro.msaa = options_.msaa;
  ro.line_width_px = static_cast<float>(k);  // one pixel of the final image
  ro.background.a = 0;                       // alpha = coverage
  std::vector<image::Image> images = renderer_->render_views(subject, cameras_, ro);
  for (auto& img : images) img = image::downsample(img, k);
  return images;
}

std::vector<ViewJudgement> ReferenceViews::judge(const render::Scene& subject) const {
  const std::vector<image::Image> test = render(subject);
  const CoverageThresholds thresholds = options_.thresholds();
  std::vector<ViewJudgement> out;
  for (std::size_t v = 0; v < test.size(); ++v)
    out.push_back(judge_coverage(images_[v], test[v], thresholds, "tree"));
  return out;
}

std::vector<ViewCheck> check_subjects(render::Renderer& renderer, const render::Scene& full,
                                      const std::vector<CheckSubject>& subjects,
                                      const lodmodel::Camera& camera, const ViewCheckOptions& options,
                                      const CheckImageSink& sink) {
  // The full-detail renders: one per (distance, view).
  std::map<double, ReferenceViews> references;
  for (const auto& s : subjects)
    if (!references.count(s.distance))
      references.emplace(std::piecewise_construct, std::forward_as_tuple(s.distance),
                         std::forward_as_tuple(renderer, full, camera, s.distance, options));

  image::CompareOptions co;  // colour, reported only
  co.compare_alpha = false;
  co.max_failing_fraction = 1.0;
  const CoverageThresholds thresholds = options.thresholds();
  image::CompareOptions heat;  // the heat-map: red where coverage or colour changed by > threshold
  heat.pixel_threshold = options.pixel_threshold;
  std::vector<ViewCheck> out;
  for (const auto& s : subjects) {
    const ReferenceViews& at = references.at(s.distance);
    const std::vector<image::Image> images = at.render(s.scene);
    for (std::size_t v = 0; v < at.cameras().size(); ++v) {
      const image::Image& ref = at.images()[v];
      const image::Image& test = images[v];
      ViewCheck c;
      c.label = s.label;
      c.level = s.level;
      c.view = at.cameras()[v].name;
      c.epsilon = s.epsilon;
      c.distance = s.distance;
      c.primitives = primitive_count(s.scene);
      c.colour = image::compare_images(ref, test, co);
      const ViewJudgement j = judge_coverage(ref, test, thresholds, "tree");
      c.stats = j.stats;
      c.failure = c.colour.size_mismatch ? c.colour.failure : j.failure;
      c.passed = c.failure.empty();
      if (sink) sink(c, ref, test, image::diff_heatmap(ref, test, heat));
      out.push_back(std::move(c));
    }
  }
  return out;
}

}  // namespace sylva::check
