// The visual proof of an impostor (`sylva impostorcheck`): the impostor and the full-detail tree
// drawn from the same camera at the impostor's switch distance, from views that are not frame
// directions, judged on coverage and colour per view.
//
// Seeds: docs/lod-model.md, the LOD error model (a representation of spatial error epsilon is within delta
// pixels from d = epsilon / (delta s(1)) on); Zhang et al. 2017 §3; the impostor's epsilon is
// libs/impostor/error_model.h's. The judgement is lodcheck's (libs/check/judge.h, docs/stages/lod.md):
//  - camera: the impostor's fov and an H-pixel image scale (H its camera's height), the eye at the
//    switch distance from the nearest point of the full-detail box (libs/render/distance_camera.h),
//    cropped around the tree (same pixels as the full H x H image, far fewer to draw);
//  - renders at k x the scale with 4x MSAA, box-averaged in linear light (weighted by alpha),
//    transparent background: a pixel's alpha is its coverage. k = max(supersample, the pixel's
//    size in atlas texels), at most 8: the full detail is drawn at least at the resolution the
//    atlas was baked at (coarser, alpha-tested cards drawn from coarse mips vanish);
//  - coverage: a pixel fails when its coverage changes by more than delta; a view passes when at
//    most max_failing_fraction of the footprint fails and the mean change is <= max_coverage_error;
//  - colour (judged here, reported by lodcheck): the mean per-channel RGB difference, weighted by
//    the coverage both renders share (libs/image/coverage.h shade_mean_error). Without a baseline
//    a view passes while it is <= max_colour_error. With one (the LOD chain's coarsest level, which
//    the impostor replaces and which is valid at the impostor's distance too, drawn from the same
//    cameras): a view passes while it is <= max(max_colour_error, colour_ratio x the level's own
//    difference in that view), and over all views the impostor's mean difference may exceed the
//    level's mean by at most colour_tolerance: an impostor may be no worse in colour than the
//    level whose place it takes. docs/stages/impostor.md says why the absolute numbers are what
//    they are on today's trees.
// Views: every (azimuth, elevation) pair of the options; each reports its angle to the nearest
// frame direction (octahedral) or card normal (billboards), so the report shows they are not
// frame directions.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/impostor/impostor_json.h"
#include "libs/impostor/octahedral.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"

namespace sylva::impostor {

struct ImpostorCheckOptions {
  double pixel_threshold = 0.5;  // delta (coverage units)
  double max_failing_fraction = 0.01;
  double max_coverage_error = 0.15;
  double max_colour_error = 0.1;   // mean per-channel RGB difference where both renders cover (a guard)
  double colour_ratio = 1.5;       // per view: at most this times the baseline's difference there ...
  double colour_tolerance = 0.02;  // ... and the mean over the views at most the baseline's mean + this
  // 12 azimuths x 3 elevations, none a frame direction of the default grids.
  std::vector<double> azimuths_deg = {7.5,   37.5,  67.5,  97.5,  127.5, 157.5,
                                      187.5, 217.5, 247.5, 277.5, 307.5, 337.5};
  std::vector<double> elevations_deg = {4, 33, 73};
  int msaa = 4;
  int supersample = 2;        // at least; see the header comment
  double distance_scale = 1;  // check at this multiple of the switch distance (tests)
  int parallax_steps = 16;    // the reference shader's ray-march steps
};

// What is checked: the impostor as impostor.json describes it and its drawable form.
struct ImpostorSubject {
  std::string label;  // for reports
  ImpostorInfo info;
  render::OctahedralImpostor
      octahedral;       // octahedral kinds: the maps and grid, drawn with the reference shader
  render::Scene cards;  // billboards: impostor.glb, drawn as any viewer draws it
};

struct ImpostorViewCheck {
  std::string label, view;
  double azimuth_deg = 0, elevation_deg = 0;
  double frame_angle_deg = 0;  // angle between this view and the nearest frame direction / card normal
  double distance = 0;
  std::size_t footprint_pixels = 0;
  double coverage_failing_fraction = 0, coverage_mean_error = 0, coverage_bias = 0;
  double colour_mean_error = 0;  // over the footprint (premultiplied-looking: includes coverage changes)
  double shade_mean_error = 0;   // judged: weighted by the coverage both renders share
  double colour_bound = 0;       // what it was judged against
  double baseline_colour = -1;   // the baseline's own difference in this view (-1: no baseline)
  std::size_t primitives = 0;    // triangles + lines drawn for the subject
  bool passed = false;
  std::string failure;
};

using ImpostorImageSink = std::function<void(const ImpostorViewCheck&, const image::Image& full,
                                             const image::Image& test, const image::Image& diff)>;

// The model an impostor replaces, measured from the same cameras to set the colour bound (see
// the header comment).
struct ColourBaseline {
  const render::Scene* scene = nullptr;  // null: no baseline
  std::string label;                     // e.g. "lod5.glb"
};

struct ImpostorCheckResult {
  std::vector<ImpostorViewCheck> views;
  double colour_mean = 0;           // the impostor's mean colour difference over the views
  double baseline_colour_max = -1;  // the baseline's largest colour difference, -1 without one
  double baseline_colour_mean = -1;
  std::string failure;  // a failure of the views together (the mean colour), else empty
  bool passed() const;  // every view passed and `failure` is empty
};

// Renders `full` and the subject from every view and judges them. Throws render::RenderError.
ImpostorCheckResult check_impostor(render::Renderer& scene_renderer,
                                   render::ImpostorRenderer& impostor_renderer, const render::Scene& full,
                                   const ImpostorSubject& subject, const ImpostorCheckOptions& options,
                                   const ColourBaseline& baseline = {}, const ImpostorImageSink& sink = {});

// The nearest distance at which the check passes: the proof's switch distance, as opposed to the
// error model's (a sufficient bound: it sums each term's worst case). Searched over multiples of
// the model's distance: the check runs at `hi` (1 = the model's distance), doubling it while it
// fails (up to 64 hi, or until no view covers a pixel); then at `lo`; then bisects in log space between the
// last failing and the first passing multiple until they differ by less than `tolerance` (relative). The
// coverage and colour judgement is check_impostor's, from the same views. Passing is not monotonic in the
// distance in principle (the colour bound follows the baseline), so the result is the passing
// end of the final bracket, checked there: every distance reported passed.
struct DistanceSearchOptions {
  double lo = 1.0 / 16;    // smallest multiple of the model's distance tried
  double hi = 1.0;         // first multiple tried
  double tolerance = 0.1;  // stop when failing and passing multiples differ by less than this
};
struct DistanceSearchStep {
  double scale = 0, distance_m = 0;
  bool passed = false;
  std::string failure;  // the first failing view's (or the views' mean colour) reason
};
struct DistanceSearchResult {
  double model_distance_m = 0;
  double proven_distance_m = 0;  // 0: no multiple up to 64 passed
  double proven_scale = 0;
  bool below_lo = false;  // it passed at `lo` already: the proven distance is an upper bound
  std::vector<DistanceSearchStep> steps;
  ImpostorCheckResult at_proven;  // the check at the proven distance
};
using DistanceStepSink = std::function<void(const DistanceSearchStep&)>;
DistanceSearchResult find_proven_distance(render::Renderer& scene_renderer,
                                          render::ImpostorRenderer& impostor_renderer,
                                          const render::Scene& full, const ImpostorSubject& subject,
                                          ImpostorCheckOptions options, const DistanceSearchOptions& search,
                                          const ColourBaseline& baseline = {},
                                          const DistanceStepSink& step_sink = {});
// (Throws std::invalid_argument unless 0 < lo <= hi and tolerance > 0.)

// The smallest angle (degrees) between `view` (centre toward the eye) and a direction the
// impostor was baked from.
double nearest_frame_angle_deg(const ImpostorInfo& info, const Vec3& view);

}  // namespace sylva::impostor
