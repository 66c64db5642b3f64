// Zhang et al. 2017 §3 (delta, epsilon, s(d)), checked in image space: the renders come from
// libs/render (the verifier's renderer), the verdict from libs/check (judge.h: coverage over the
// tree's footprint, since a distant tree is a few percent of the frame), the colour numbers and
// the heat-map from libs/image (OpenImageIO).
#include "stages/lod/check/lodcheck.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <span>
#include <utility>

#include "libs/check/judge.h"
#include "libs/image/resample.h"
#include "libs/render/distance_camera.h"

namespace sylva::lod {

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

render::Camera check_camera(const render::Bounds& full_bounds, double distance, double azimuth_deg,
                            double elevation_deg, double fov_y_rad) {
  render::Camera cam =
      render::camera_at_box_distance(full_bounds, distance, azimuth_deg, elevation_deg, fov_y_rad);
  cam.name = view_name(azimuth_deg);  // one elevation per run: views are named by azimuth
  return cam;
}

std::vector<ViewCheck> check_subjects(render::Renderer& renderer, const render::Scene& full,
                                      const std::vector<CheckSubject>& subjects, const Camera& chain_camera,
                                      const LodCheckOptions& options, const CheckImageSink& sink) {
  const int k = std::max(1, options.supersample);
  const int frame = chain_camera.height_px;
  // Renders at k x the window, box-averaged down to it (header: supersampling).
  auto render_views = [&](const render::Scene& scene, const std::vector<render::Camera>& cams, int window) {
    render::RenderOptions ro;
    ro.width = ro.height = window * k;
    ro.msaa = options.msaa;
    ro.line_width_px = static_cast<float>(k);  // one pixel of the final image
    ro.background.a = 0;                       // alpha = coverage
    std::vector<image::Image> images = renderer.render_views(scene, cams, ro);
    for (auto& img : images) img = image::downsample(img, k);
    return images;
  };
  const render::Bounds bounds = full.bounds();
  // Per distance: the views' cameras, cropped to the centred window that holds the tree (the
  // same for both views and for every subject at that distance, so the images compare pixel
  // for pixel; outside it both images are empty). A far level is a small window.
  struct Views {
    int window = 0;
    std::vector<render::Camera> cameras;
  };
  std::map<double, Views> views;
  for (const auto& s : subjects) {
    auto [it, fresh] = views.try_emplace(s.distance);
    if (!fresh) continue;
    std::vector<render::Camera> cams;
    for (double az : options.azimuths_deg) {
      cams.push_back(check_camera(bounds, s.distance, az, options.elevation_deg, chain_camera.fov_y_rad));
      it->second.window = std::max(
          it->second.window, options.crop ? crop_window(bounds, cams.back(), frame, kCropMarginPx) : frame);
    }
    for (auto& c : cams) c = cropped(c, it->second.window, frame);
    it->second.cameras = std::move(cams);
  }

  // The full-detail renders: one per (distance, view).
  std::map<double, std::vector<image::Image>> full_images;
  for (const auto& [d, v] : views) full_images.emplace(d, render_views(full, v.cameras, v.window));

  image::CompareOptions co;  // colour, reported only
  co.compare_alpha = false;
  co.max_failing_fraction = 1.0;
  check::CoverageThresholds thresholds;
  thresholds.pixel_threshold = options.pixel_threshold;
  thresholds.max_failing_fraction = options.max_failing_fraction;
  thresholds.max_coverage_error = options.max_coverage_error;
  image::CompareOptions heat;  // the heat-map: red where coverage or colour changed by > threshold
  heat.pixel_threshold = options.pixel_threshold;
  std::vector<ViewCheck> out;
  for (const auto& s : subjects) {
    const Views& at = views.at(s.distance);
    const std::vector<render::Camera>& cams = at.cameras;
    const std::vector<image::Image> images = render_views(s.scene, cams, at.window);
    for (std::size_t v = 0; v < cams.size(); ++v) {
      const image::Image& ref = full_images.at(s.distance)[v];
      const image::Image& test = images[v];
      ViewCheck c;
      c.label = s.label;
      c.level = s.level;
      c.view = cams[v].name;
      c.epsilon = s.epsilon;
      c.distance = s.distance;
      c.primitives = primitive_count(s.scene);
      c.colour = image::compare_images(ref, test, co);
      const check::ViewJudgement j = check::judge_coverage(ref, test, thresholds, "tree");
      c.stats = j.stats;
      c.failure = c.colour.size_mismatch ? c.colour.failure : j.failure;
      c.passed = c.failure.empty();
      if (sink) sink(c, ref, test, image::diff_heatmap(ref, test, heat));
      out.push_back(std::move(c));
    }
  }
  return out;
}

render::Scene branches_only(const render::Scene& scene) {
  render::Scene out = scene;
  for (auto& mesh : out.meshes) {
    std::erase_if(mesh.primitives, [&](const render::Primitive& p) {
      if (p.material < 0 || p.material >= static_cast<int>(scene.materials.size())) return true;
      const std::string& name = scene.materials[static_cast<std::size_t>(p.material)].name;
      return name != "bark" && name != "bark_lines";
    });
  }
  return out;
}

}  // namespace sylva::lod
