// Zhang et al. 2017 §3 (delta, epsilon, s(d)), checked in image space: the renders come from
// libs/render (the verifier's renderer), the comparison from libs/image (OpenImageIO). Only the
// footprint numbers are computed here, because the library's statistics are over the whole frame
// and a distant tree is a few percent of it.
#include "stages/lod/check/lodcheck.h"

#include "libs/image/resample.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <span>
#include <utility>

namespace sylva::lod {

namespace {

// Euclidean distance from p to the axis-aligned box b (0 inside).
double box_distance(const render::Bounds& b, const Eigen::Vector3d& p) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double lo = b.min[k], hi = b.max[k];
    const double e = p[k] < lo ? lo - p[k] : (p[k] > hi ? p[k] - hi : 0.0);
    s += e * e;
  }
  return std::sqrt(s);
}

std::string view_name(double azimuth_deg) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "az%g", azimuth_deg);
  return buf;
}

std::size_t primitive_count(const render::Scene& s) { return s.triangle_count() + s.line_count(); }

// Coverage (alpha) and colour statistics over the footprint: the pixels either image covers.
void add_footprint_stats(const image::Image& ref, const image::Image& test, double pixel_threshold, ViewCheck& c) {
  const auto& rb = ref.bytes();
  const auto& tb = test.bytes();
  double coverage_sum = 0, coverage_signed = 0, colour_sum = 0;
  std::size_t failing = 0;
  for (std::size_t p = 0; p + 3 < rb.size() && p + 3 < tb.size(); p += 4) {
    if (rb[p + 3] == 0 && tb[p + 3] == 0) continue;
    ++c.footprint_pixels;
    const double signed_change = (int(tb[p + 3]) - int(rb[p + 3])) / 255.0;
    coverage_sum += std::abs(signed_change);
    coverage_signed += signed_change;
    failing += std::abs(signed_change) > pixel_threshold ? 1 : 0;
    for (int ch = 0; ch < 3; ++ch) colour_sum += std::abs(int(rb[p + ch]) - int(tb[p + ch])) / 255.0;
  }
  if (c.footprint_pixels == 0) return;
  const double n = double(c.footprint_pixels);
  c.coverage_failing_fraction = double(failing) / n;
  c.coverage_mean_error = coverage_sum / n;
  c.coverage_bias = coverage_signed / n;
  c.colour_mean_error = colour_sum / (3.0 * n);
}

}  // namespace

render::Camera check_camera(const render::Bounds& full_bounds, double distance, double azimuth_deg,
                            double elevation_deg, double fov_y_rad) {
  render::Bounds b = full_bounds;
  if (b.empty()) {
    b.extend(render::Vec3(-0.5f, -0.5f, -0.5f));
    b.extend(render::Vec3(0.5f, 0.5f, 0.5f));
  }
  const double a = azimuth_deg * std::numbers::pi / 180, e = elevation_deg * std::numbers::pi / 180;
  const Eigen::Vector3d dir(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
  const Eigen::Vector3d c = b.center().cast<double>();
  // The box distance grows monotonically along the ray once outside: bisect for the point at
  // exactly `distance` from the box.
  double lo = 0, hi = distance + 2.0 * b.radius() + 1.0;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (box_distance(b, c + mid * dir) < distance ? lo : hi) = mid;
  }
  render::Camera cam;
  cam.eye = (c + hi * dir).cast<float>();
  cam.target = c.cast<float>();
  cam.up = std::abs(dir.y()) > 0.999 ? render::Vec3::UnitZ() : render::Vec3::UnitY();
  cam.fov_y_deg = static_cast<float>(fov_y_rad * 180 / std::numbers::pi);
  cam.z_near = static_cast<float>(std::max(1e-3, 0.5 * distance));
  cam.z_far = static_cast<float>(hi + 2.0 * b.radius() + 1.0);
  cam.name = view_name(azimuth_deg);
  return cam;
}

std::vector<ViewCheck> check_subjects(render::Renderer& renderer, const render::Scene& full,
                                      const std::vector<CheckSubject>& subjects, const Camera& chain_camera,
                                      const LodCheckOptions& options, const CheckImageSink& sink) {
  const int k = std::max(1, options.supersample);
  render::RenderOptions ro;
  ro.width = ro.height = chain_camera.height_px * k;
  ro.msaa = options.msaa;
  ro.line_width_px = static_cast<float>(k);  // one pixel of the final image
  ro.background.a = 0;                       // alpha = coverage
  auto render_views = [&](const render::Scene& scene, const std::vector<render::Camera>& cams) {
    std::vector<image::Image> images = renderer.render_views(scene, cams, ro);
    for (auto& img : images) img = image::downsample(img, k);
    return images;
  };
  const render::Bounds bounds = full.bounds();
  auto camera_for = [&](double distance, double az) {
    return check_camera(bounds, distance, az, options.elevation_deg, chain_camera.fov_y_rad);
  };

  // The full-detail renders: one per distinct (distance, view), in one upload.
  std::map<std::pair<double, double>, std::size_t> full_index;
  std::vector<render::Camera> full_cameras;
  for (const auto& s : subjects)
    for (double az : options.azimuths_deg)
      if (full_index.emplace(std::pair(s.distance, az), full_cameras.size()).second)
        full_cameras.push_back(camera_for(s.distance, az));
  const std::vector<image::Image> full_images = render_views(full, full_cameras);

  image::CompareOptions co;  // colour, reported only
  co.compare_alpha = false;
  co.max_failing_fraction = 1.0;
  image::CompareOptions heat;  // the heat-map: red where coverage or colour changed by > threshold
  heat.pixel_threshold = options.pixel_threshold;
  std::vector<ViewCheck> out;
  for (const auto& s : subjects) {
    std::vector<render::Camera> cams;
    for (double az : options.azimuths_deg) cams.push_back(camera_for(s.distance, az));
    const std::vector<image::Image> images = render_views(s.scene, cams);
    for (std::size_t v = 0; v < cams.size(); ++v) {
      const image::Image& ref = full_images[full_index.at({s.distance, options.azimuths_deg[v]})];
      const image::Image& test = images[v];
      ViewCheck c;
      c.label = s.label;
      c.level = s.level;
      c.view = cams[v].name;
      c.epsilon = s.epsilon;
      c.distance = s.distance;
      c.primitives = primitive_count(s.scene);
      c.colour = image::compare_images(ref, test, co);
      add_footprint_stats(ref, test, options.pixel_threshold, c);
      char buf[256];
      if (c.colour.size_mismatch) {
        c.failure = c.colour.failure;
      } else if (c.coverage_failing_fraction > options.max_failing_fraction) {
        std::snprintf(buf, sizeof buf, "coverage of %.2f%% of the tree's %zu pixels changed by more than %.3g (allowed %.2f%%)",
                      100 * c.coverage_failing_fraction, c.footprint_pixels, options.pixel_threshold,
                      100 * options.max_failing_fraction);
        c.failure = buf;
      } else if (c.coverage_mean_error > options.max_coverage_error) {
        std::snprintf(buf, sizeof buf, "mean coverage change over the tree's %zu pixels is %.4f (allowed %.4f)",
                      c.footprint_pixels, c.coverage_mean_error, options.max_coverage_error);
        c.failure = buf;
      }
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
