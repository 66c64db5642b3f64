// The octahedral and hemi-octahedral maps (Praun & Hoppe 2003; Cigolle et al. 2014 §3.3) as the
// impostor grid uses them; octahedral.h states every formula. The GLSL in
// libs/render/shaders/octahedral_impostor.vert is the same code, line for line.
#include "libs/impostor/octahedral.h"

#include <algorithm>
#include <cmath>

namespace sylva::impostor {

namespace {

double sgn(double x) { return x >= 0 ? 1.0 : -1.0; }

}  // namespace

Vec3 clamp_to_hemisphere(const Vec3& v) {
  if (v.y() >= 0) return v.normalized();
  Vec3 h(v.x(), 0, v.z());
  if (h.norm() < 1e-12) return Vec3::UnitZ();
  return h.normalized();
}

Vec2 encode_direction(const Vec3& v_in, bool hemi) {
  const Vec3 v = hemi ? clamp_to_hemisphere(v_in) : v_in;
  const double l1 = std::abs(v.x()) + std::abs(v.y()) + std::abs(v.z());
  const Vec3 q = v / (l1 > 0 ? l1 : 1.0);
  if (hemi) return Vec2(q.x() + q.z(), q.x() - q.z());
  if (q.y() >= 0) return Vec2(q.x(), q.z());
  return Vec2((1 - std::abs(q.z())) * sgn(q.x()), (1 - std::abs(q.x())) * sgn(q.z()));
}

Vec3 decode_direction(const Vec2& p_in, bool hemi) {
  const Vec2 p(std::clamp(p_in.x(), -1.0, 1.0), std::clamp(p_in.y(), -1.0, 1.0));
  Vec3 q;
  if (hemi) {
    const double x = 0.5 * (p.x() + p.y()), z = 0.5 * (p.x() - p.y());
    q = Vec3(x, 1 - std::abs(x) - std::abs(z), z);
  } else {
    q = Vec3(p.x(), 1 - std::abs(p.x()) - std::abs(p.y()), p.y());
    if (q.y() < 0) q = Vec3((1 - std::abs(p.y())) * sgn(p.x()), q.y(), (1 - std::abs(p.x())) * sgn(p.y()));
  }
  return q.normalized();
}

Vec3 frame_direction(int i, int j, int n, bool hemi) {
  const double s = 2.0 / double(n - 1);
  return decode_direction(Vec2(i * s - 1, j * s - 1), hemi);
}

FrameBasis frame_basis(const Vec3& dir) {
  FrameBasis b;
  b.dir = dir.normalized();
  if (std::abs(b.dir.y()) > 1 - 1e-6) {
    b.right = Vec3::UnitX();
  } else {
    b.right = Vec3::UnitY().cross(b.dir).normalized();
  }
  b.up = b.dir.cross(b.right).normalized();
  return b;
}

FrameBlend blend_frames(const Vec3& view_dir, int n, bool hemi) {
  const Vec2 p = encode_direction(view_dir, hemi);
  const double m = double(n - 1);
  const Vec2 g = ((p.array() + 1.0) * 0.5 * m).matrix();
  const int cx = std::clamp(int(std::floor(g.x())), 0, n - 2);
  const int cy = std::clamp(int(std::floor(g.y())), 0, n - 2);
  const double fx = std::clamp(g.x() - cx, 0.0, 1.0), fy = std::clamp(g.y() - cy, 0.0, 1.0);
  FrameBlend b;
  if (fx + fy <= 1) {
    b.i = {cx, cx + 1, cx};
    b.j = {cy, cy, cy + 1};
    b.weight = {1 - fx - fy, fx, fy};
  } else {
    b.i = {cx + 1, cx + 1, cx};
    b.j = {cy + 1, cy, cy + 1};
    b.weight = {fx + fy - 1, 1 - fy, 1 - fx};
  }
  return b;
}

namespace {

// Visits view directions on a lattice of samples x samples points in every grid cell (the
// cell's corners and edges included), calling f(view, blend).
template <typename F>
void for_each_view(int n, bool hemi, int samples, F&& f) {
  const double m = double(n - 1);
  for (int cy = 0; cy < n - 1; ++cy)
    for (int cx = 0; cx < n - 1; ++cx)
      for (int sy = 0; sy <= samples; ++sy)
        for (int sx = 0; sx <= samples; ++sx) {
          const Vec2 g(cx + double(sx) / samples, cy + double(sy) / samples);
          const Vec2 p = (g / m * 2.0).array() - 1.0;
          const Vec3 v = decode_direction(p, hemi);
          f(v, blend_frames(v, n, hemi));
        }
}

double angle_between(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)); }

}  // namespace

double view_error_factor(int n, bool hemi, int samples) {
  double worst = 0;
  for_each_view(n, hemi, samples, [&](const Vec3& v, const FrameBlend& b) {
    double e = 0;
    for (int k = 0; k < 3; ++k)
      e += b.weight[k] * (1 - std::cos(angle_between(v, frame_direction(b.i[k], b.j[k], n, hemi))));
    worst = std::max(worst, e);
  });
  return worst;
}

double max_blend_angle(int n, bool hemi, int samples) {
  double worst = 0;
  for_each_view(n, hemi, samples, [&](const Vec3& v, const FrameBlend& b) {
    for (int k = 0; k < 3; ++k)
      if (b.weight[k] > 0)
        worst = std::max(worst, angle_between(v, frame_direction(b.i[k], b.j[k], n, hemi)));
  });
  return worst;
}

}  // namespace sylva::impostor
