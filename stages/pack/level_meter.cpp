// Issue 14: "image error at the band's switch distance ... measured with the lodcheck renderer,
// not guessed". The measurement is lodcheck's (libs/check/view_check.h) on the pack's own files.
#include "stages/pack/level_meter.h"

#include <algorithm>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "libs/render/gltf_scene.h"

namespace sylva::pack {

RenderedLevelMeter::RenderedLevelMeter(render::Renderer& renderer, render::Scene full,
                                       const lodmodel::Camera& camera, const check::ViewCheckOptions& options)
    : renderer_(renderer), full_(std::move(full)), camera_(camera), options_(options) {}

LevelMeter::Result RenderedLevelMeter::measure(int key, const std::string& glb, double distance_m) {
  if (check_cancelled) check_cancelled();
  auto scene = scenes_.find(key);
  if (scene == scenes_.end())
    scene = scenes_.emplace(key, render::load_gltf_scene_from_memory(glb, "candidate level")).first;
  auto ref = references_.find(distance_m);
  if (ref == references_.end())
    ref = references_
              .emplace(std::piecewise_construct, std::forward_as_tuple(distance_m),
                       std::forward_as_tuple(renderer_, full_, camera_, distance_m, options_))
              .first;
  const std::vector<check::ViewJudgement> views = ref->second.judge(scene->second);
  ++subject_renders_;
  Result r;
  r.error.passed = true;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const check::ViewJudgement& j = views[v];
    r.error.failing_fraction = std::max(r.error.failing_fraction, j.stats.failing_fraction);
    r.error.coverage_mean_error = std::max(r.error.coverage_mean_error, j.stats.coverage_mean_error);
    if (!j.passed() && r.error.passed) {
      r.error.passed = false;
      r.failure = ref->second.cameras()[v].name + ": " + j.failure;
    }
  }
  return r;
}

}  // namespace sylva::pack
