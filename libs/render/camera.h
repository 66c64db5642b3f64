// Cameras and camera sets (configs/cameras/*.yaml).
//
// A camera set names the views a verification or a `sylva render` draws, the image size and
// the multisampling level. A view is either an orbit around the scene's bounding sphere
// (azimuth / elevation / distance factor, so one set fits every asset) or an explicit
// eye / target / up. resolve() turns a view into a concrete Camera for a given scene.
//
// File format (docs/renderer.md has the full reference):
//   version: 1
//   width: 1024            # image size in pixels, 1..16384
//   height: 1024
//   msaa: 4                # optional, samples per pixel: 1 (off), 2, 4, 8 or 16; default 4
//   supersample: 1         # optional, 1..4: draw k x the size and average k x k blocks; default 1
//   fov_y_deg: 40          # optional default vertical field of view for the views; default 40
//   views:
//     - name: front        # [A-Za-z0-9_.-]+, unique; used in output file names
//       orbit: { azimuth_deg: 0, elevation_deg: 10, distance_factor: 1.1 }
//     - name: trunk
//       eye: [0, 1.5, 6]
//       target: [0, 1.5, 0]
//       up: [0, 1, 0]      # optional, default +Y
//       fov_y_deg: 30      # optional, overrides the set's default
//
// Azimuth 0 looks at the scene from +Z (glTF's front), 90 from +X; elevation 90 looks straight
// down. With distance_factor 1 the bounding sphere just fits the narrower image axis; orbit
// may give distance_m (metres from the box centre) instead of distance_factor.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "libs/render/scene.h"

namespace sylva::render {

// A resolved camera: right-handed look-at with a symmetric perspective projection.
struct Camera {
  std::string name;  // the view's name (for output files and reports)
  Vec3 eye = Vec3(0, 0, 5);
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitY();
  float fov_y_deg = 40.f;  // vertical field of view, degrees, in (0, 180)
  float z_near = 0.1f;     // clip planes, metres, 0 < z_near < z_far
  float z_far = 100.f;

  Mat4 view_matrix() const;                    // world -> eye space (OpenGL convention, -Z forward)
  Mat4 projection_matrix(float aspect) const;  // eye -> clip space; aspect = width / height
};

struct OrbitView {
  float azimuth_deg = 0.f;      // around +Y, 0 = from +Z, 90 = from +X
  float elevation_deg = 0.f;    // [-90, 90], positive = from above
  float distance_factor = 1.f;  // > 0; 1 = bounding sphere fits the image
  float distance_m = 0.f;       // > 0 overrides distance_factor: metres from the box centre
};

struct LookAtView {
  Vec3 eye = Vec3(0, 0, 5);
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitY();
};

struct CameraView {
  std::string name;
  std::variant<OrbitView, LookAtView> placement;
  float fov_y_deg = 40.f;
};

struct CameraSet {
  std::string source;  // file it was read from
  int width = 1024;
  int height = 1024;
  int msaa = 4;
  int supersample = 1;  // RenderOptions::supersample
  std::vector<CameraView> views;
};

// All problems found in a camera-set file. what() lists them, one per line, each as
//   "configs/cameras/x.yaml:7:20: error: unknown key 'azimuth' in orbit; did you mean 'azimuth_deg'?"
// (line and column 1-based). errors() gives the same lines one by one.
class CameraSetError : public std::runtime_error {
 public:
  explicit CameraSetError(std::vector<std::string> errors);
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  std::vector<std::string> errors_;
};

// Reads and validates a camera-set file; collects every error before throwing CameraSetError.
CameraSet load_camera_set(const std::filesystem::path& path);
// The same, from text; `source_name` is used as the file name in messages.
CameraSet parse_camera_set(std::string_view yaml_text, const std::string& source_name);

// A concrete camera for `view` looking at a scene with world bounds `scene_bounds`, for an image
// of the given aspect (width / height). Near and far planes enclose the bounding sphere (near is
// at least far / 10^4). An empty scene is treated as a unit box at the origin.
Camera resolve(const CameraView& view, const Bounds& scene_bounds, float aspect);

}  // namespace sylva::render
