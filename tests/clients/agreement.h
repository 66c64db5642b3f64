// The second-renderer check: does a glTF client (three.js) show what sylva's renderer, and so
// sylva's verifier, sees? Both renderers draw the same file from the same cameras (same eye,
// target, up, fov, clip planes, 512 x 512, 4x MSAA, transparent background, the same light);
// the images are compared by silhouette agreement and colour (docs/clients.md, "The second
// renderer", justifies every bound).
//
// Both are measured on 4 x 4 pixel blocks (128 x 128 blocks of a 512 px view): the two
// rasterisers place their 4 MSAA samples differently, and a tree is mostly sub-pixel twigs and
// leaves of 1-3 px, so single pixels differ by sampling alone; 16 pixels (64 samples) average
// that out while a real defect (missing or extra geometry, a wrong colour, a moved camera) spans
// blocks. With a = a block's mean coverage (alpha in [0, 1]) and C its mean colour (straight,
// from the premultiplied mean):
//   coverage IoU  = sum over blocks of min(a_s, a_c) / sum of max(a_s, a_c)
//                   (1 = identical silhouettes; partial coverage counts fractionally)
//   colour diff   = mean over blocks covered by both (a >= 0.25 in each) of
//                   (|dR| + |dG| + |dB|) / 3 of C, in 8-bit sRGB levels
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/camera.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"

namespace sylva::clients {

inline constexpr int kViewSize = 512;
inline constexpr int kBlock = 16;         // pixels per block side
inline constexpr double kCovered = 0.25;  // a block counts as covered from this mean coverage

// What a file is, for its bound (docs/clients.md).
enum class Kind { kMesh, kDracoMesh, kLevel, kLineLevel, kRibbons, kChain, kImpostor, kForestTile };
const char* kind_name(Kind k);

struct Bound {
  double min_iou = 0.9;
  double max_colour = 0;  // 8-bit levels
};
Bound bound_for(Kind k);

// The two views of every file: "tree" (front, the whole bounding box fills the frame) and
// "crown" (front, a close-up of the top third of the box, eye in front of the box).
std::vector<render::Camera> views(const render::Bounds& bounds);

struct Agreement {
  double iou = 0;
  double colour = 0;
  std::size_t both = 0;    // blocks covered by both
  std::size_t either = 0;  // blocks covered by either
};
// Throws std::invalid_argument when the sizes differ.
Agreement compare(const image::Image& sylva, const image::Image& client);

// sylva's render options for the check (transparent background, 4x MSAA, 512 px).
render::RenderOptions render_options();

// The three.js renderer (tests/clients/threejs_render.mjs) for a batch of jobs.
struct ClientRender {
  std::filesystem::path file, out;
  render::Camera camera;
};
struct LodCheck {
  std::filesystem::path file;
  double fov_y_deg = 45, radius = 0;
  std::vector<double> distances;
};
struct ClientResult {
  bool unavailable = false;  // a tool is missing (exit 3): message says which
  bool ok = false;
  std::string message;    // stderr of the script on failure
  nlohmann::json result;  // RESULT.json
};
// A file three.js only loads (no picture): the primitives it would draw, per MSFT_lod level when
// msft_lod (RESULT.json "load_checks").
struct LoadCheck {
  std::filesystem::path file;
  bool msft_lod = false;
};
ClientResult run_threejs(const std::vector<ClientRender>& renders, const std::vector<LodCheck>& lod_checks,
                         const std::filesystem::path& work_dir,
                         const std::vector<LoadCheck>& load_checks = {});

// One row of the agreement table.
struct Row {
  std::string client = "three.js";
  std::string file;  // as shown (node/file)
  std::string view;
  Kind kind = Kind::kMesh;
  Agreement a;
  Bound bound;
  bool passed() const { return a.iou >= bound.min_iou && a.colour <= bound.max_colour; }
  std::string line()
      const;  // "three.js  lod_oak/lod3.gltf  crown  level  IoU 0.973 >= 0.90  colour 3.1 <= 8.0  ok"
};

}  // namespace sylva::clients
