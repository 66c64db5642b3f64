#include "stages/verify/verify_info.h"

namespace sylva {

namespace {
// Bump whenever the bytes of any output can change (report formats, file naming, verdicts).
constexpr int kVersion = 2;
}  // namespace

StageInfo verify_stage_info() {
  StageInfo info;
  info.name = "verify";
  info.version = kVersion;
  info.summary =
      "render fixed views of every glTF input, compare with reference images, report (JSON, JUnit, HTML)";
  info.inputs = InputSpec{{"mesh", "lod", "impostor", "forest", "pack"},
                          1,
                          -1,
                          "artifacts with .glb/.gltf files; each file is one asset, named after its node"};
  info.output_type = "report";
  info.params = {
      Param::path("cameras").describe("camera set (configs/cameras/verify.yaml: 384 px, 4x MSAA, 4 views)"),
      Param::dir("references").describe("directory of reference images <asset>__<view>.png"),
      Param::real("pixel_threshold", 0.016)
          .range(0, 1)
          .describe("a pixel fails when any channel differs by more than this (full scale 1; 0.016 = 4/255)"),
      Param::real("max_failing_fraction", 0.01)
          .range(0, 1)
          .describe("a view fails when more than this fraction of its pixels fail"),
      Param::real("min_psnr_db", 0.0)
          .range(0, 200)
          .describe("a view also fails when its PSNR is below this (dB); 0 = not checked"),
      Param::boolean("compare_alpha", true).describe("compare the alpha channel too"),
  };
  return info;
}

}  // namespace sylva
