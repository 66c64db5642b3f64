// The verification core: render every view of a camera set for each asset, compare each image
// with its reference, and collect the verdicts in a Report (report.h writes it as JSON, JUnit XML
// and one self-contained HTML page). Used by stage `verify` (verify_stage.h) and by the
// `sylva verify` command, so both judge identically. Reference: docs/stages/verify.md.
//
// File names. A view `v` of asset `a` is the file `a__v.png`: the rendering among the outputs
// and, by the same name, the reference in the references directory; its heat map is
// `a__v.diff.png`. Asset and view names are [A-Za-z0-9_.-]+, so these are flat file names.
//
// Verdicts. judge_view() is the pure part: a view passes when a reference exists, has the same
// size, at most `max_failing_fraction` of its pixels differ by more than `pixel_threshold` in
// some channel (libs/image/compare.h, OpenImageIO's compare), and, when `min_psnr_db` > 0, the
// PSNR reaches it. An asset that cannot be loaded (bad GLB, missing texture) gives an `error`
// case for each view instead of stopping the run, so the report still shows everything else.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/fileio/file_source.h"
#include "libs/image/compare.h"
#include "libs/image/image.h"
#include "libs/render/camera.h"
#include "libs/render/renderer.h"

namespace sylva::verify {

// A failure that stops the whole run (an output that cannot be written, duplicate asset names,
// rendering errors other than a bad asset). what() is one line.
class VerifyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One thing to draw: a .glb or .gltf file and the name its images carry.
struct Asset {
  std::string name;  // [A-Za-z0-9_.-]+, unique within a run
  std::filesystem::path
      file;  // .glb / .gltf (textures resolved relative to it), or a forest's instances.json
  // A forest (libs/render/forest_view.h): drawn with its LOD levels per tree from the views of its
  // own camera set (cameras.yaml beside instances.json), not from the run's camera set.
  bool forest = false;
};

struct Thresholds {
  double pixel_threshold = 0.016;      // per channel, full scale = 1 (Blender: idiff -fail 0.016)
  double max_failing_fraction = 0.01;  // of the pixels (Blender: idiff -failpercent 1)
  double min_psnr_db = 0;              // > 0: a view also fails below this PSNR (dB); 0 = unchecked
  bool compare_alpha = true;

  image::CompareOptions compare_options() const;
};

enum class CaseStatus {
  kPassed,
  kFailed,            // compared and differs too much (or size mismatch, or PSNR too low)
  kMissingReference,  // no <asset>__<view>.png in the references directory
  kError,             // the asset or its reference could not be read
};
// "passed", "failed", "missing_reference", "error" (the words report.json uses).
const char* status_name(CaseStatus s);

// One asset seen from one view.
struct CaseResult {
  std::string asset, view;
  CaseStatus status = CaseStatus::kError;
  std::string message;     // empty when passed; otherwise one sentence saying why
  std::string image_file;  // "<asset>__<view>.png": the output and the reference's name; empty on kError
  std::string diff_file;   // "<asset>__<view>.diff.png" when a reference was compared, else empty
  bool compared = false;   // `compare` holds numbers (a reference was read)
  image::CompareResult compare;
  int width = 0, height = 0;  // of the rendering (0 on kError)
  // Encoded PNG bytes, kept in memory for the HTML report only (empty when absent).
  std::string reference_png, image_png, diff_png;
};

struct Report {
  std::string device;  // Renderer::device_description()
  Thresholds thresholds;
  int width = 0, height = 0, msaa = 0;  // of the camera set
  std::vector<std::string> views;       // camera-set order
  std::vector<std::string> assets;      // input order
  std::vector<CaseResult> cases;        // asset order, then view order
  // Files in the references directory named after an asset of this run ("<asset>__x.png") whose
  // view the camera set no longer has: candidates for deletion, never a failure.
  std::vector<std::string> unused_references;

  std::size_t count(CaseStatus s) const;
  bool passed() const { return !cases.empty() && count(CaseStatus::kPassed) == cases.size(); }
};

// "<asset>__<view>.png" and "<asset>__<view>.diff.png".
std::string image_file_name(const std::string& asset, const std::string& view);
std::string diff_file_name(const std::string& asset, const std::string& view);

// Pure: the verdict for `rendered` against `reference` (nullptr: no reference image). Fills
// every field except the PNG bytes.
CaseResult judge_view(const std::string& asset, const std::string& view, const image::Image* reference,
                      const image::Image& rendered, const Thresholds& thresholds);

// Where run_verification() puts its files and how it checks for Ctrl-C.
struct RunEnv {
  render::Renderer& renderer;
  // The path to write output file `name` to (the stage maps it to StageContext::output_path,
  // the command to a directory). Called once per file written.
  std::function<std::filesystem::path(const std::string& name)> output_path;
  std::function<void()> check_cancelled;  // may be empty; may throw to stop the run
  // Where the assets and references are read from (the stage: its declared inputs); nullptr:
  // the disk.
  const fileio::FileSource* files = nullptr;
};

// Renders every view of `cameras` for every asset (one upload per asset), writes
// `<asset>__<view>.png` and, where a reference exists, `<asset>__<view>.diff.png` through
// env.output_path, and judges each view against `references_dir/<asset>__<view>.png`.
// Assets that fail to load become kError cases. Throws VerifyError for invalid or duplicate
// asset names, for files it cannot write, and when rendering itself fails
// (render::RenderUnavailableError is passed through unchanged so callers can say "no EGL").
Report run_verification(const std::vector<Asset>& assets, const render::CameraSet& cameras,
                        const std::filesystem::path& references_dir, const Thresholds& thresholds,
                        const RunEnv& env);

}  // namespace sylva::verify
