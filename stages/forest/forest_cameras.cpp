// Celba §5.2: "two scene animation paths: the walkthrough through the forest as someone walks or
// runs in the forest and flight above the forest", the flight starting "with low altitude flight
// upon the forest" and ending "in much higher altitude". Both are sampled at a few evenly spaced
// instants (frames_per_path), so a verify report shows a forest from the ground and from the air,
// near trees at their finest levels and far ones at their coarsest. The walkthrough runs south to
// north (+z to -z) through the middle, from 10 % of the depth inside the south edge to 10 % inside
// the north edge, the eye moved sideways off any trunk it would stand in; the flight rises from
// outside the south-west corner, low, to high above the forest's middle, always looking at its
// centre.
#include "stages/forest/forest_cameras.h"

#include <algorithm>
#include <cmath>

#include "libs/render/camera.h"

namespace sylva::forest {

namespace {

// The nearest tree position to (x, z) on the ground, metres.
double clearance(const Forest& f, double x, double z) {
  double best = INFINITY;
  for (const Instance& in : f.instances)
    best = std::min(best, std::hypot(in.position[0] - x, in.position[2] - z));
  return best;
}

}  // namespace

std::string forest_camera_set(const Forest& f, const Terrain& terrain, const ForestCameraOptions& o) {
  const double w = f.extent_max[0] - f.extent_min[0], d = f.extent_max[1] - f.extent_min[1];
  const double cx = 0.5 * (f.extent_min[0] + f.extent_max[0]), cz = 0.5 * (f.extent_min[1] + f.extent_max[1]);
  double top = 0;
  for (const Instance& in : f.instances) {
    const Species& s = f.species[in.species];
    top = std::max(top, in.position[1] + s.bounds.max[1] * in.scale[1]);
  }
  const double ground_c = terrain.height(cx, cz);
  render::CameraSet set;
  set.width = o.width_px;
  set.height = o.height_px;
  set.msaa = o.msaa;
  set.supersample = o.supersample;
  set.fov_y_deg = o.fov_y_deg;
  const int n = std::max(1, o.frames_per_path);
  auto add = [&](const std::string& name, double ex, double ey, double ez, double tx, double ty, double tz) {
    render::LookAtView look;
    look.eye = {ex, ey, ez};
    look.target = {tx, ty, tz};
    set.views.push_back({name, look, float(set.fov_y_deg)});
  };
  for (int k = 0; k < n; ++k) {
    const double t = n == 1 ? 0.5 : double(k) / double(n - 1);
    const double z = cz + d * (0.4 - 0.8 * t);
    double x = cx;
    for (int step = 0; step < 40 && clearance(f, x, z) < 1.5; ++step)
      x = cx + (step % 2 ? -1 : 1) * 1.0 * (step / 2 + 1);
    const double g = terrain.height(x, z);
    add("walk_" + std::to_string(k), x, g + o.eye_height_m, z, x, g + o.eye_height_m, z - 20);
  }
  const double high = std::max(2.0 * top, 0.8 * std::max(w, d));
  for (int k = 0; k < n; ++k) {
    const double t = n == 1 ? 0.5 : double(k) / double(n - 1);
    const double ex = cx - 0.6 * w + t * 0.6 * w, ez = cz + 0.6 * d - t * 0.6 * d;
    const double ey = terrain.height(ex, ez) + std::max(o.eye_height_m, top * 0.5) + t * (high - top * 0.5);
    add("fly_" + std::to_string(k), ex, ey, ez, cx, ground_c, cz - 0.1 * d);
  }
  add("overview", cx, ground_c + 0.6 * std::max(w, d), cz + 0.9 * d, cx, ground_c, cz);
  return render::write_camera_set(
      set, "The forest camera set written by stage forest (docs/stages/forest.md, \"Cameras\").");
}

}  // namespace sylva::forest
