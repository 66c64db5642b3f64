// Zhang et al. 2017 §3 (delta, epsilon, s(d)), checked in image space: the renders come from
// libs/render (the verifier's renderer), the comparison from libs/image (OpenImageIO). Only the
// footprint numbers are computed here, because the library's statistics are over the whole frame
// and a distant tree is a few percent of it.
#include "stages/lod/check/lodcheck.h"

#include "libs/image/coverage.h"
#include "libs/image/resample.h"
#include "libs/render/distance_camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <span>
#include <utility>

namespace sylva::lod {

namespace {

std::string view_name(double azimuth_deg) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "az%g", azimuth_deg);
  return buf;
}

std::size_t primitive_count(const render::Scene& s) { return s.triangle_count() + s.line_count(); }

void add_footprint_stats(const image::Image& ref, const image::Image& test, double pixel_threshold, ViewCheck& c) {
  const image::FootprintStats f = image::footprint_stats(ref, test, pixel_threshold);
  c.footprint_pixels = f.footprint_pixels;
  c.coverage_failing_fraction = f.failing_fraction;
  c.coverage_mean_error = f.coverage_mean_error;
  c.coverage_bias = f.coverage_bias;
  c.colour_mean_error = f.colour_mean_error;
}

}  // namespace

render::Camera check_camera(const render::Bounds& full_bounds, double distance, double azimuth_deg,
                            double elevation_deg, double fov_y_rad) {
  render::Camera cam = render::camera_at_box_distance(full_bounds, distance, azimuth_deg, elevation_deg, fov_y_rad);
  cam.name = view_name(azimuth_deg);  // one elevation per run: views are named by azimuth
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
