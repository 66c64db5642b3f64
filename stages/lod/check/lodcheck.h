// The visual proof of a LOD chain (`sylva lodcheck`): draw each level at its switch distance and
// the full-detail tree from the same camera, and measure how much the images differ.
//
// Seeds: Zhang et al. 2017 §3 (a level of spatial error epsilon seen from distance d projects to
// at most delta = epsilon / s(d) pixels; switching at d = epsilon / (delta s(1)) keeps every
// level's error at most delta pixels, "invisible" for delta = 0.5); DESIGN.md "LOD error model".
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
// over the footprint) but not judged: unlit lines with three fixed normals are
// not lit like the cylinders they replace (Zhang §5.5, §6), a tone change the bound says nothing
// about. The verdict is libs/check's (judge.h), shared with impostorcheck and the forest check;
// docs/stages/lod.md justifies the thresholds.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "libs/image/compare.h"
#include "libs/image/coverage.h"
#include "libs/image/image.h"
#include "libs/render/camera.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"
#include "stages/lod/chain.h"

namespace sylva::lod {

struct LodCheckOptions {
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

// The eye for a check at `distance` metres from the box (see the header comment). `height_px`
// sets the square image the camera is for.
render::Camera check_camera(const render::Bounds& full_bounds, double distance, double azimuth_deg,
                            double elevation_deg, double fov_y_rad);

// Optional sink for the images of a check: (subject label, level, view, full render, subject
// render, diff heat-map).
using CheckImageSink = std::function<void(const ViewCheck&, const image::Image& full,
                                          const image::Image& test, const image::Image& diff)>;

// Renders `full` once per distinct (distance, view) and every subject at its distance, compares.
// Throws render::RenderError when rendering fails. Results in subject order, views inner.
std::vector<ViewCheck> check_subjects(render::Renderer& renderer, const render::Scene& full,
                                      const std::vector<CheckSubject>& subjects, const Camera& chain_camera,
                                      const LodCheckOptions& options, const CheckImageSink& sink = {});

// Keeps only the branch primitives of a scene (materials "bark" and "bark_lines" as lod_gltf.h
// names them): for comparing branch simplification without the foliage.
render::Scene branches_only(const render::Scene& scene);

}  // namespace sylva::lod
