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
//
// This file is the format's one reader (parse_camera_set, load_camera_set) and writer
// (write_camera_set: the forest stage's cameras.yaml).
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

// Points in metres as the file states them (double: what a writer was given is what it writes;
// resolve() rounds them to the renderer's floats).
struct LookAtView {
  Eigen::Vector3d eye = Eigen::Vector3d(0, 0, 5);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
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
  int supersample = 1;    // RenderOptions::supersample
  double fov_y_deg = 40;  // the file's top-level fov_y_deg: the views' default, in (0, 180)
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

// The camera-set file of `set` (a set parse_camera_set accepts): `comment` (may be empty; one
// "# " line per line of it), then version 1, width, height, msaa, supersample (when > 1), the
// set's fov_y_deg (6 significant digits) and the views in order: name, then `orbit` (its numbers
// to float precision) or eye and target (and up, unless +Y) in metres with 4 decimals, then the
// view's fov_y_deg when it is not the set's (as a float). Reading it back gives the set, up to
// those precisions.
std::string write_camera_set(const CameraSet& set, std::string_view comment = {});

// A concrete camera for `view` looking at a scene with world bounds `scene_bounds`, for an image
// of the given aspect (width / height). Near and far planes enclose the bounding sphere (near is
// at least far / 10^4). An empty scene is treated as a unit box at the origin.
Camera resolve(const CameraView& view, const Bounds& scene_bounds, float aspect);

}  // namespace sylva::render
