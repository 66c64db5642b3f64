// The image-space proof of a level of detail, shared by `sylva lodcheck` (stages/lod/check,
// app/lodcheck_command.cpp) and the pack stage's measured level choice (stages/pack): draw a
// subject (a LOD level, an impostor, another simplifier's model) and the full-detail tree from
// the same cameras at a distance d, and judge how much the images differ (judge.h).
//
// Seeds: Zhang et al. 2017 §3 (a level of spatial error epsilon seen from distance d projects to
// at most delta = epsilon / s(d) pixels; switching at d = epsilon / (delta s(1)) keeps every
// level's error at most delta pixels, "invisible" for delta = 0.5); docs/lod-model.md.
//
// The camera of a check. The bound holds for geometry at distance >= d from the eye, so the eye
// is placed at distance d from the nearest point of the full-detail tree's bounding box: it looks
// horizontally (elevation 0, or the given elevation) at the box centre from azimuth a (0 = from
// +Z, 90 = from +X), with the chain's vertical field of view and an H x H image (H = the chain's
// image height, the H of s(d), so a pixel in the check is a pixel of the error bound).
//
// What is judged is coverage, not colour. The renders have a transparent background, so a
// pixel's alpha is the fraction of it the tree covers (supersampled, below). A level whose
// geometry is within delta pixels of the full detail moves a straight edge by at most delta, which
// changes the coverage of any pixel by at most delta: so a pixel "fails" when its coverage changes
// by more than delta (pixel_threshold defaults to delta = 0.5), and a view passes when few of the
// tree's pixels (its footprint: covered in either image) fail and the mean coverage change over
// the footprint is small. Colour is reported (OpenImageIO's comparison over RGB, and the mean
// over the footprint) but not judged: unlit lines with three fixed normals are not lit like the
// cylinders they replace (Zhang §5.5, §6), a tone change the bound says nothing about. The
// verdict is judge.h's, shared with impostorcheck and the forest check; docs/stages/lod.md
// justifies the thresholds.
//
// Rendering goes through render::Renderer (the real one, or a test fake); no other side effect.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "libs/check/judge.h"
#include "libs/image/compare.h"
#include "libs/image/coverage.h"
#include "libs/image/image.h"
#include "libs/lodmodel/lod_model.h"
#include "libs/render/camera.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"

namespace sylva::check {

struct ViewCheckOptions {
  // A pixel fails when its coverage changes by more than this (0..1): delta's 0.5 px.
  double pixel_threshold = 0.5;
  // A view passes while failing pixels <= this fraction of the footprint ...
  double max_failing_fraction = 0.01;
  // ... and the mean coverage change over the footprint is at most this.
  double max_coverage_error = 0.15;
  std::vector<double> azimuths_deg = {0, 90};
  double elevation_deg = 0;
  int msaa = 4;  // samples per pixel, as the verifier renders
  // Renders are made at supersample x H and box-averaged (linear light) down to H, so twigs and
  // needles far thinner than a pixel are integrated (supersample^2 x msaa samples per pixel)
  // rather than hit or missed by 4 sample positions; both images are treated alike. 2 gives 16
  // samples per pixel; 4 costs 4x the fill.
  int supersample = 2;
  // Render only the centred window of the H x H frame that holds the full detail's projected
  // bounding box (plus a margin): the same eye and pixels, a small image for a far level.
  bool crop = true;

  CoverageThresholds thresholds() const;
};

// The eye for a check at `distance` metres from the box (see the header comment), named
// "az<azimuth>".
render::Camera check_camera(const render::Bounds& full_bounds, double distance, double azimuth_deg,
                            double elevation_deg, double fov_y_rad);

// The full detail drawn from a check's views at one distance: the cameras (one per azimuth,
// cropped to the centred window that holds the full detail's box, the same for every view),
// the window's side in pixels and the full-detail images. A subject rendered with render()
// compares with images() pixel for pixel.
class ReferenceViews {
 public:
  // Renders `full` (throws render::RenderError when rendering fails).
  ReferenceViews(render::Renderer& renderer, const render::Scene& full, const lodmodel::Camera& camera,
                 double distance, const ViewCheckOptions& options);

  // `subject` from the same cameras, supersampled and reduced as the reference.
  std::vector<image::Image> render(const render::Scene& subject) const;

  // The coverage verdict of every view of `subject` ("tree" is the noun of the sentences).
  std::vector<ViewJudgement> judge(const render::Scene& subject) const;

  const std::vector<render::Camera>& cameras() const { return cameras_; }
  const std::vector<image::Image>& images() const { return images_; }
  int window() const { return window_; }
  double distance() const { return distance_; }

 private:
  render::Renderer* renderer_;
  ViewCheckOptions options_;
  double distance_ = 0;
  int window_ = 0;
  std::vector<render::Camera> cameras_;
  std::vector<image::Image> images_;
};

// One model to check: a level of a chain (or another simplifier's model with the same budget).
struct CheckSubject {
  std::string label;      // "sylva", "gltfpack", ...: for reports
  std::size_t level = 0;  // level index: sets the epsilon and distance below
  double epsilon = 0;     // m
  double distance = 0;    // switch distance d, m (> 0)
  render::Scene scene;
};

struct ViewCheck {
  std::string label;
  std::size_t level = 0;
  std::string view;  // "az0", "az90", ...
  double epsilon = 0, distance = 0;
  // Coverage and colour over the footprint (pixels covered in either image), the level against the
  // full detail: coverage_bias > 0 means the level covers more.
  image::FootprintStats stats;
  image::CompareResult colour;  // RGB over the whole image (threshold 0.016, reported only)
  std::size_t primitives = 0;   // triangles + lines drawn for this subject
  bool passed = false;
  std::string failure;  // empty when passed, else one sentence
};

// Optional sink for the images of a check: (the view's result, full render, subject render,
// diff heat-map).
using CheckImageSink = std::function<void(const ViewCheck&, const image::Image& full,
                                          const image::Image& test, const image::Image& diff)>;

// Renders `full` once per distinct (distance, view) and every subject at its distance, compares.
// Throws render::RenderError when rendering fails. Results in subject order, views inner.
std::vector<ViewCheck> check_subjects(render::Renderer& renderer, const render::Scene& full,
                                      const std::vector<CheckSubject>& subjects,
                                      const lodmodel::Camera& camera, const ViewCheckOptions& options,
                                      const CheckImageSink& sink = {});

}  // namespace sylva::check
