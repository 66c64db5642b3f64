// Frames and cards of an impostor atlas (layout.h). Octahedral: Brucks 2018 on the grid of
// libs/impostor/octahedral.h. Billboards: SpeedTree's ring of vertical cards plus a horizontal one.
#include "stages/impostor/layout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "libs/impostor/octahedral.h"

namespace sylva::impostor {

namespace {

Vec3d to_array(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
render::Vec3 to_f(const Vec3& v) { return v.cast<float>(); }

render::BakeView view_for(const Vec3& center, const Vec3& dir, double half_w, double half_h, double depth,
                          int x, int y, int w, int h) {
  const FrameBasis b = frame_basis(dir);
  render::BakeView v;
  v.center = to_f(center);
  v.right = to_f(b.right);
  v.up = to_f(b.up);
  v.dir = to_f(b.dir);
  v.half_width = float(half_w);
  v.half_height = float(half_h);
  v.depth_radius = float(depth);
  v.x = x, v.y = y, v.w = w, v.h = h;
  return v;
}

Card card_for(const render::BakeView& v, const std::string& name) {
  Card c;
  c.name = name;
  c.dir = to_array(v.dir.cast<double>());
  c.right = to_array(v.right.cast<double>());
  c.up = to_array(v.up.cast<double>());
  c.center = to_array(v.center.cast<double>());
  c.half_width = v.half_width;
  c.half_height = v.half_height;
  c.x = v.x, c.y = v.y, c.w = v.w, c.h = v.h;
  c.cutout = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};  // the whole frame, counter-clockwise seen from dir
  return c;
}

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

SourceGeometry measure(const render::Scene& scene) {
  const render::Bounds b = scene.bounds();
  check(!b.empty(), "the source has no vertices");
  SourceGeometry g;
  const Vec3 c = b.center().cast<double>();
  g.bounds_min = to_array(b.min.cast<double>());
  g.bounds_max = to_array(b.max.cast<double>());
  g.center = to_array(c);
  double r2 = 0, h2 = 0;
  for (const render::Mesh& mesh : scene.meshes)
    for (const render::Mat4& m : mesh.instances)
      for (const render::Primitive& p : mesh.primitives)
        for (const render::Vec3& v : p.positions) {
          const Vec3 w = (m * v.homogeneous()).hnormalized().cast<double>() - c;
          r2 = std::max(r2, w.squaredNorm());
          h2 = std::max(h2, w.x() * w.x() + w.z() * w.z());
        }
  // Float rounding of the vertices: widen by a part in 10^5 so no vertex sits outside.
  g.radius = std::sqrt(r2) * (1 + 1e-5) + 1e-6;
  g.horizontal_radius = std::sqrt(h2) * (1 + 1e-5) + 1e-6;
  return g;
}

namespace {

// The (hemi-)octahedral kinds: frames_per_side^2 frames over the (hemi)sphere of directions, and
// the fallback cross of cards. `c` is the sphere's centre, `fill` the frame's extent over the
// sphere's radius; `out` has its padding.
void plan_octahedral(const LayoutParams& p, const SourceGeometry& g, const Vec3& c, double fill,
                     Layout& out) {
  const int f = p.frame_px;
  const bool hemi = p.kind == Kind::kHemiOctahedral;
  const int n = p.frames_per_side;
  check(n >= 2 && n <= 64, "frames_per_side must be in 2..64");
  check(std::int64_t(n) * f <= 16384,
        "the atlas (frames_per_side x frame_px = " + std::to_string(n * f) + " px) is larger than 16384 px");
  out.atlas_width = out.atlas_height = n * f;
  out.frame_half_extent = g.radius * fill;
  const double depth = g.radius * 1.001;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      out.views.push_back(view_for(c, frame_direction(i, j, n, hemi), out.frame_half_extent,
                                   out.frame_half_extent, depth, i * f, j * f, f, f));
  // The fallback cross: the frames nearest the four cardinal horizon directions, two planes
  // through the centre. No horizontal card: seen from the side it would be a dense stripe
  // across the crown (the whole top view squeezed into a sliver), and far trees are seen
  // from the side.
  struct Target {
    const char* name;
    Vec3 dir;
  };
  const std::vector<Target> targets = {
      {"az0", Vec3::UnitZ()}, {"az90", Vec3::UnitX()}, {"az180", -Vec3::UnitZ()}, {"az270", -Vec3::UnitX()}};
  for (const Target& t : targets) {
    int best = 0;
    double best_dot = -2;
    for (int v = 0; v < int(out.views.size()); ++v) {
      const double d = out.views[std::size_t(v)].dir.cast<double>().dot(t.dir);
      if (d > best_dot + 1e-12) best_dot = d, best = v;
    }
    out.cards.push_back(card_for(out.views[std::size_t(best)], t.name));
    out.card_view.push_back(best);
  }
}

// Billboards: `cards` vertical views around the vertical axis, then the top view, in a grid of
// square frames. Arguments as plan_octahedral's.
void plan_billboards(const LayoutParams& p, const SourceGeometry& g, const Vec3& c, double fill,
                     Layout& out) {
  const int f = p.frame_px;
  check(p.cards >= 3 && p.cards <= 64, "cards must be in 3..64");
  const int count = p.cards + (p.top_card ? 1 : 0);
  const int cols = int(std::ceil(std::sqrt(double(count))));
  const int rows = (count + cols - 1) / cols;
  check(std::int64_t(cols) * f <= 16384, "the billboard atlas is larger than 16384 px");
  out.atlas_width = cols * f;
  out.atlas_height = rows * f;
  const double half_height = 0.5 * (g.bounds_max[1] - g.bounds_min[1]);
  out.frame_half_extent = std::max(g.horizontal_radius, half_height) * fill;
  for (int k = 0; k < p.cards; ++k) {
    const double a = 2 * std::numbers::pi * k / p.cards;
    const Vec3 dir(std::sin(a), 0, std::cos(a));
    out.views.push_back(view_for(c, dir, out.frame_half_extent, out.frame_half_extent,
                                 g.horizontal_radius * 1.001, (k % cols) * f, (k / cols) * f, f, f));
    out.cards.push_back(
        card_for(out.views.back(), "az" + std::to_string(int(std::lround(a * 180 / std::numbers::pi)))));
    out.card_view.push_back(k);
  }
  if (p.top_card) {
    const int k = p.cards;
    out.views.push_back(view_for(c, Vec3::UnitY(), g.horizontal_radius * fill, g.horizontal_radius * fill,
                                 half_height * 1.001, (k % cols) * f, (k / cols) * f, f, f));
    out.cards.push_back(card_for(out.views.back(), "top"));
    out.card_view.push_back(k);
  }
}

}  // namespace

Layout plan_layout(const LayoutParams& p, const SourceGeometry& g) {
  check(p.frame_px >= 16 && p.frame_px <= 8192, "frame_px must be in 16..8192");
  check(p.mip_levels >= 0 && p.mip_levels <= 12, "mip_levels must be in 0..12");
  Layout out;
  out.padding_px = 1 << p.mip_levels;
  check(4 * out.padding_px < p.frame_px, "mip_levels " + std::to_string(p.mip_levels) +
                                             " needs a padding of " + std::to_string(out.padding_px) +
                                             " texels, more than a quarter of frame_px " +
                                             std::to_string(p.frame_px));
  // The sphere's disc spans frame_px - 2 padding texels: W = R F / (F - 2 p).
  const double fill = double(p.frame_px) / double(p.frame_px - 2 * out.padding_px);
  const Vec3 c(g.center[0], g.center[1], g.center[2]);
  if (p.kind != Kind::kBillboards)
    plan_octahedral(p, g, c, fill, out);
  else
    plan_billboards(p, g, c, fill, out);
  return out;
}

double atlas_texel(const LayoutParams& params, const SourceGeometry& geometry) {
  const Layout layout = plan_layout(params, geometry);
  return 2 * layout.frame_half_extent / params.frame_px;
}

}  // namespace sylva::impostor
