// The LOD error model (docs/lod-model.md): how a spatial error in metres becomes pixels on the
// screen, from where a level is valid, how much of the screen a tree covers (MSFT_lod's
// MSFT_screencoverage), and how blended lines stand for sub-pixel branches. Every stage, library
// and check command computes these quantities here, nowhere else.
//
// Seeds: Zhang et al. 2017 §3 (permitted pixel error delta, permitted spatial error epsilon),
// §5.4 (the LOD sequence), §6 and eq. 12 (semi-transparent lines); Celba 2007 eq. 4.1-4.5 (a
// screen-area metric of the same camera); Microsoft's MSFT_lod glTF extension (screen coverage).
//
// Plain C++ (no GL, no images, no JSON): anything may link it.
//
// Units: metres (distances, epsilon, radii), pixels (delta), radians (the camera's fov; files and
// parameters state degrees and convert with radians() / degrees()). Every function is pure and
// computes in one fixed order of operations, which the glTF and JSON bytes of the pipeline depend
// on: change none of them without bumping the versions of the stages that use it.
#pragma once

#include <limits>
#include <span>

namespace sylva::lodmodel {

// The camera the error model is for: vertical field of view phi and image height H. (A view
// camera that also has a position is the renderer's, libs/render/camera.h; it is built from this
// one where a check draws, libs/render/distance_camera.h.)
struct Camera {
  double fov_y_rad = 0.785398163397448;  // phi, in (0, pi); the default is 45°
  int height_px = 1080;                  // H, >= 1
  friend bool operator==(const Camera&, const Camera&) = default;
};

// deg * pi / 180 and rad * 180 / pi: the one conversion between a file's or a parameter's degrees
// and the model's radians (degrees(radians(x)) need not be x to the bit).
double radians(double deg);
double degrees(double rad);
// {radians(fov_y_deg), height_px}.
Camera camera_from_degrees(double fov_y_deg, int height_px);

// tan(phi / 2).
double tan_half_fov(const Camera& camera);

// s(d) = 2 d tan(phi/2) / H: the metres one pixel spans at distance d >= 0 (m).
double pixel_size(const Camera& camera, double distance);

// d = epsilon / (delta s(1)): the distance (m) from which a level of spatial error epsilon (m) stays
// within delta pixels (delta > 0).
double switch_distance(const Camera& camera, double epsilon, double delta);

// epsilon = d delta s(1): the spatial error (m) a switch distance d (m) stands for at delta pixels;
// the inverse of switch_distance.
double spatial_error(const Camera& camera, double distance, double delta);

// s at a level's own switch distance: epsilon / delta (m per pixel; delta > 0).
double switch_pixel_size(double epsilon, double delta);

// The factor that moves a switch distance valid for (from, from_delta) to the distance where
// (to, to_delta) allows the same spatial error: (from_delta s_from(1)) / (to_delta s_to(1)).
double distance_scale(const Camera& from, double from_delta, const Camera& to, double to_delta);

// MSFT_screencoverage at distance d (m) of a bounding sphere of radius R (m), as the extension and
// Babylon.js define it (the sphere's screen area over the screen's, aspect 1), clamped to 1:
//   c(d) = min(1, pi R^2 / (2 d tan(phi/2))^2)      in [0, 1]
// The first form takes tan(phi/2) (tan_half_fov, or coverage_tan_half_fov from a chain's values).
double screen_coverage(double tan_half_fov, double radius, double distance);
double screen_coverage(const Camera& camera, double radius, double distance);

// The distance at which the coverage of a sphere of radius R falls to `coverage` (the inverse of
// c(d) below the clamp): d = R sqrt(pi) / (2 tan(phi/2) sqrt(c)); +infinity for c <= 0.
double coverage_distance(const Camera& camera, double radius, double coverage);

// tan(phi/2) from one unclamped coverage c (0 < c < 1) of a sphere of radius R > 0 at distance d:
// R sqrt(pi / c) / (2 d).
double coverage_tan_half_fov(double radius, double coverage, double distance);

// The axis-aligned box of a model's positions and the radius of its bounding sphere, the R of the
// screen coverage: half the box's diagonal, as Babylon.js bounds a mesh.
class BoundingBox {
 public:
  void extend(double x, double y, double z);
  // Every (x, y, z) triple of `xyz` (a trailing incomplete triple is ignored).
  void extend(std::span<const float> xyz);
  bool empty() const { return !(lo_[0] <= hi_[0]); }
  // 0.5 sqrt(dx^2 + dy^2 + dz^2) (m); 0 for an empty box.
  double radius() const;

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  double lo_[3] = {kInf, kInf, kInf};
  double hi_[3] = {-kInf, -kInf, -kInf};
};

// Blended lines (docs/lod-model.md "Lines"). An internode far below a pixel is drawn as three
// lines on the same pixels (Zhang §5.5), which blend over each other: for the three to cover a
// fraction c of a pixel, each is drawn with alpha a = 1 - (1 - c)^(1/3).

// a(c) for c clamped to [0, 1] (1 for c >= 1), computed without cancellation for tiny c.
double line_alpha(double coverage);
// c(a) = 1 - (1 - a)^3, the inverse, for a in [0, 1).
double line_coverage(double alpha);
// The alpha each line of a level is drawn with: eq. 12's alpha (2 / rho, the branch's pixel
// coverage for pixels of E3 metres, i.e. at delta = 1 px) times delta is the coverage at the
// level's switch distance, a(eq12_alpha delta).
double drawn_line_alpha(double eq12_alpha, double delta);
// A line drawn with alpha a at its level's switch distance s, drawn from d instead (scale = s / d
// > 0): a pixel at d is d / s of one at s, so its coverage becomes min(1, c(a) s / d). 1 for
// a >= 1; a < 0 counts as 0.
double line_alpha_at(double alpha, double scale);

}  // namespace sylva::lodmodel
