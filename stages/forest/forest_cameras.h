// The forest camera set (issue 13 "Forest views"): eye positions in the forest along the two
// two animation paths of Celba §5.2 (a walkthrough, and a flight from low to high altitude), plus
// an overview, written as a camera-set file (libs/render/camera.h's format, explicit eye/target
// views) that `sylva render`, the verify stage and `sylva lodcheck` read with the forest.
#pragma once

#include <string>

#include "libs/forest/instances.h"
#include "stages/forest/fields.h"

namespace sylva::forest {

struct ForestCameraOptions {
  int width_px = 960, height_px = 540, msaa = 4;
  int supersample = 2;  // the camera set's `supersample` (with msaa 4: hybrid, docs/renderer.md)
  double fov_y_deg = 45;
  int frames_per_path = 2;    // views per path (>= 1)
  double eye_height_m = 1.7;  // walkthrough eye above the ground
};

// The camera-set YAML for `forest` (terrain gives the ground height; may be empty).
std::string forest_camera_set(const Forest& forest, const Terrain& terrain,
                              const ForestCameraOptions& options);

}  // namespace sylva::forest
