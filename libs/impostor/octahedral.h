// The (hemi-)octahedral frame grid of an impostor atlas: which direction each frame was baked
// from, how a view direction selects and weights three frames, and each frame's image basis.
//
// Sources: the octahedral map of unit vectors (Praun & Hoppe 2003, "Spherical parametrization and
// remeshing"; Cigolle et al. 2014, "A survey of efficient representations for independent unit
// vectors", §3.3 "oct"), as octahedral impostors use it (Brucks 2018, "Octahedral impostors");
// the hemi-octahedral variant maps the upper hemisphere alone onto the whole square (Cigolle et
// al. §3.3; Brucks 2018 "hemi-octahedron"). docs/stages/impostor.md writes every formula out, and
// the reference GLSL (libs/render/shaders/octahedral_impostor.{vert,frag}) implements the same
// ones; the tests pin both to these.
//
// Conventions (object space, glTF's: metres, Y up, right-handed; azimuth 0 = from +Z):
//  - A "direction" points from the impostor's centre TOWARD the viewer (unit length).
//  - Grid point p in [-1, 1]^2. Hemi-octahedral (directions with y >= 0):
//      encode: q = v / (|v.x| + |v.y| + |v.z|);  p = (q.x + q.z, q.x - q.z)
//      decode: q = ((p.x + p.y) / 2, 1 - |q.x| - |q.z|, (p.x - p.y) / 2);  v = q / |q|
//    The square's border is the horizon; its corners are azimuths 0 (p = (1,-1)), 90 (1,1),
//    180 (-1,1), 270 (-1,-1); its centre is straight up.
//    Octahedral (every direction):
//      encode: q = v / |v|_1;  p = (q.x, q.z) if q.y >= 0, else
//              ((1 - |q.z|) sgn(q.x), (1 - |q.x|) sgn(q.z))
//      decode: q = (p.x, 1 - |p.x| - |p.y|, p.y); if q.y < 0: (q.x, q.z) =
//              ((1 - |p.y|) sgn(p.x), (1 - |p.x|) sgn(p.y));  v = q / |q|     (sgn(0) = +1)
//  - N x N frames sit on the grid's VERTICES: frame (i, j) (column i left to right, row j top to
//    bottom of the atlas image) was baked from decode(p) with p = (2i/(N-1) - 1, 2j/(N-1) - 1),
//    so the horizon (hemi) is sampled exactly by the border frames.
//  - Frame basis for a direction d: right r = normalize(Y x d) and up u = d x r; when |d.y| >
//    1 - 1e-6, r = +X (so a frame from straight above has -Z at its top, like the renderer's
//    orbit cameras).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

namespace sylva::impostor {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

// Grid point p in [-1,1]^2 of a unit direction. Hemi: a direction below the horizon is first
// moved onto it (clamp_to_hemisphere).
Vec2 encode_direction(const Vec3& v, bool hemi);
// Unit direction of a grid point p in [-1,1]^2 (clamped into the square).
Vec3 decode_direction(const Vec2& p, bool hemi);

// The direction a hemi impostor uses for v: v itself when v.y >= 0, else v with y = 0
// (renormalised; straight down gives +Z). So a view from below shows the horizon frames.
Vec3 clamp_to_hemisphere(const Vec3& v);

// Direction of frame (i, j) of an N x N grid (N >= 2, 0 <= i, j < N).
Vec3 frame_direction(int i, int j, int n, bool hemi);

struct FrameBasis {
  Vec3 right, up, dir;  // orthonormal, right x up = dir
};
FrameBasis frame_basis(const Vec3& dir);

// The three frames a view direction blends, with barycentric weights (sum 1, each >= 0). The
// grid coordinate g = (p + 1) / 2 (N - 1) falls in cell c = min(floor(g), N - 2) with fraction f;
// the cell's lower-left triangle (f.x + f.y <= 1) blends c, c + (1,0), c + (0,1) with weights
// (1 - f.x - f.y, f.x, f.y); the other blends c + (1,1), c + (1,0), c + (0,1) with
// (f.x + f.y - 1, 1 - f.y, 1 - f.x).
struct FrameBlend {
  std::array<int, 3> i{}, j{};
  std::array<double, 3> weight{};
};
FrameBlend blend_frames(const Vec3& view_dir, int n, bool hemi);

// The view-interpolation error factor of a grid: the largest, over every view direction the
// grid covers, of sum_k w_k (1 - cos theta_k), theta_k the angle between the view and frame k
// (docs/stages/impostor.md, "Switch distance"). Multiplied by the sphere radius it bounds how far
// a depth-corrected frame moves an outline point of a convex part (Pasman 2001, "image with
// depth": the first-order parallax term vanishes, the second-order R (1 - cos theta) remains).
// Evaluated on a lattice of `samples` x `samples` points per grid cell (both triangles).
double view_error_factor(int n, bool hemi, int samples = 16);

// The largest angle (radians) between a view direction and the farthest frame it blends.
double max_blend_angle(int n, bool hemi, int samples = 16);

}  // namespace sylva::impostor
