// The pack stage's LevelMeter (pack_core.h): a candidate level's file as shipped (quantised,
// compressed: decoded by libs/render's loader as a client decodes it) drawn from the views of
// `sylva lodcheck` at a band start and judged against the full-detail tree with lodcheck's
// verdict (libs/check/view_check.h: the same cameras, crop, supersampling and thresholds). The
// renderer is the one side effect: the stage gives the process's headless renderer, tests a fake.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>

#include "libs/check/view_check.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"
#include "stages/pack/pack_core.h"

namespace sylva::pack {

class RenderedLevelMeter final : public LevelMeter {
 public:
  // `full`: the full-detail tree (the lod artifact's full.glb); `camera`: the chain's (lod.json's
  // camera: the H and field of view its pixel error is for).
  RenderedLevelMeter(render::Renderer& renderer, render::Scene full, const lodmodel::Camera& camera,
                     const check::ViewCheckOptions& options);

  // Renders the full detail once per distance and each candidate's file once per distance it is
  // measured at; the worse view's numbers, the first failing view's sentence. Throws
  // std::runtime_error (a file the loader refuses, render::RenderError).
  Result measure(int key, const std::string& glb, double distance_m) override;

  // Called before every measurement (the stage's cancellation check); may throw.
  std::function<void()> check_cancelled;

  std::size_t subject_renders() const { return subject_renders_; }      // calls that rendered a level
  std::size_t reference_renders() const { return references_.size(); }  // distances of full renders

 private:
  render::Renderer& renderer_;
  render::Scene full_;
  lodmodel::Camera camera_;
  check::ViewCheckOptions options_;
  std::map<double, check::ReferenceViews> references_;  // by distance
  std::map<int, render::Scene> scenes_;                 // decoded candidate files, by key
  std::size_t subject_renders_ = 0;
};

}  // namespace sylva::pack
