// The adapter of stage `verify`: declares the parameters, turns the inputs into assets, runs the
// core (verify_core.h) and writes the reports (report.h). A stage writes only its outputs, so it
// never touches the references directory: accepting new images is `sylva verify --update-refs`.
#include "stages/verify/verify_stage.h"

#include <string>

#include "libs/forest/instances.h"
#include "libs/render/camera.h"
#include "libs/render/shared_renderer.h"
#include "stages/verify/report.h"
#include "stages/verify/verify_info.h"

namespace sylva {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

class VerifyStage final : public Stage {
 public:
  explicit VerifyStage(std::function<render::Renderer&()> renderer) : renderer_(std::move(renderer)) {
    info_ = verify_stage_info();
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. The camera set and the assets.
    render::CameraSet cameras;
    try {
      cameras = render::parse_camera_set(ctx.read_param_file("cameras"), ctx.param_file("cameras").string());
    } catch (const render::CameraSetError& e) {
      throw StageError(e.what());
    }
    const std::vector<verify::Asset> assets = verify::assets_from_inputs(ctx.inputs());
    const verify::Thresholds thresholds = verify::thresholds_from_params(ctx.params());

    // 2. Render, compare, write images and reports.
    verify::Report report;
    try {
      render::Renderer& renderer = renderer_();
      const verify::RunEnv env{renderer, [&](const std::string& name) { return ctx.output_path(name); },
                               [&] { ctx.check_cancelled(); }, &ctx.files()};
      report = verify::run_verification(assets, cameras, ctx.param_file("references"), thresholds, env);
      ctx.check_cancelled();
      // A failing run publishes nothing, so its reports would be thrown away: write them only
      // when they will be kept. `sylva verify` writes them in every case.
      if (report.passed()) verify::write_reports(report, env.output_path);
    } catch (const verify::VerifyError& e) {
      throw StageError(e.what());
    } catch (const render::RenderError& e) {  // including RenderUnavailableError: no EGL
      throw StageError(e.what());
    }

    // 3. Any view that did not pass fails the node (and the build: exit code 1).
    if (!report.passed())
      throw StageError(
          verify::summary_line(report) +
          " (run 'sylva verify RECIPE' for report.html, or add --update-refs to accept the new images)");
  }

 private:
  StageInfo info_;
  std::function<render::Renderer&()> renderer_;
};

}  // namespace

std::unique_ptr<Stage> make_verify_stage(std::function<render::Renderer&()> renderer) {
  return std::make_unique<VerifyStage>(std::move(renderer));
}

std::unique_ptr<Stage> make_verify_stage() {
  return make_verify_stage([]() -> render::Renderer& { return verify::shared_renderer(); });
}

namespace verify {

std::vector<Asset> assets_from_inputs(const std::vector<InputArtifact>& inputs) {
  std::vector<Asset> assets;
  for (const InputArtifact& in : inputs) {
    if (in.type == "forest") {  // one asset: the forest seen from its own cameras
      const ArtifactFile* f = in.file(forest::kInstancesJson);
      if (!f) throw StageError("input '" + in.node + "' (type forest) has no instances.json");
      assets.push_back({in.node, f->path, true});
      continue;
    }
    std::vector<const ArtifactFile*> files;
    for (const ArtifactFile& f : in.files)
      if (ends_with(f.name, ".glb") || ends_with(f.name, ".gltf")) files.push_back(&f);
    if (files.empty())
      throw StageError("input '" + in.node + "' (type " + in.type + ") has no .glb or .gltf file to verify");
    for (const ArtifactFile* f : files) {
      const std::string stem = f->name.substr(0, f->name.rfind('.'));
      assets.push_back({files.size() == 1 ? in.node : in.node + "." + stem, f->path});
    }
  }
  return assets;
}

Thresholds thresholds_from_params(const Value::Object& params) {
  auto real = [&](const char* name, double def) {
    auto it = params.find(name);
    return it == params.end() ? def : it->second.as_real();
  };
  Thresholds t;
  t.pixel_threshold = real("pixel_threshold", t.pixel_threshold);
  t.max_failing_fraction = real("max_failing_fraction", t.max_failing_fraction);
  t.min_psnr_db = real("min_psnr_db", t.min_psnr_db);
  if (auto it = params.find("compare_alpha"); it != params.end()) t.compare_alpha = it->second.as_bool();
  return t;
}

render::Renderer& shared_renderer() { return render::shared_renderer(); }

}  // namespace verify
}  // namespace sylva
