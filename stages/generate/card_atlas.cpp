// The card atlas (card_atlas.h): each cell is drawn by compositing anti-aliased primitives —
// tapered capsules (stems, petioles, needles) and leaf blades (a species silhouette) — in
// physical card coordinates, front to back in painter's order.
#include "stages/generate/card_atlas.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace sylva::generate {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMargin = 0.03;  // fraction of the cell kept transparent at its edges

struct P2 {
  double x = 0, y = 0;
};
P2 operator+(P2 a, P2 b) { return {a.x + b.x, a.y + b.y}; }
P2 operator-(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
P2 operator*(P2 a, double s) { return {a.x * s, a.y * s}; }
double dot(P2 a, P2 b) { return a.x * b.x + a.y * b.y; }
double len(P2 a) { return std::sqrt(dot(a, a)); }
P2 unit_at(double angle) { return {std::sin(angle), std::cos(angle)}; }  // angle from +y (the stem's way)

struct Rgb {
  double r = 0, g = 0, b = 0;
};
Rgb mix(const tree::Color& a, const tree::Color& b, double t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}
Rgb scaled(Rgb c, double s) { return {c.r * s, c.g * s, c.b * s}; }

// One cell being drawn: premultiplied colour and alpha, composited "over" in drawing order.
class Cell {
 public:
  Cell(int w, int h, double width_m, double height_m)
      : w_(w),
        h_(h),
        W_(width_m),
        H_(height_m),
        px_(std::max(width_m / w, height_m / h)),
        rgb_(static_cast<std::size_t>(w) * h * 3, 0.0),
        a_(static_cast<std::size_t>(w) * h, 0.0) {}

  double pixel_m() const { return px_; }
  double width() const { return W_; }
  double height() const { return H_; }

  // Pixel centre (i, j) in card coordinates: x across in [-W/2, W/2], y along in [0, H].
  P2 at(int i, int j) const { return {((i + 0.5) / w_ - 0.5) * W_, (j + 0.5) / h_ * H_}; }

  // Visits the pixels whose centres lie in the card-space box [lo, hi].
  template <class F>
  void each(P2 lo, P2 hi, F&& f) {
    const int i0 = std::max(0, static_cast<int>(std::floor((lo.x / W_ + 0.5) * w_ - 1)));
    const int i1 = std::min(w_ - 1, static_cast<int>(std::ceil((hi.x / W_ + 0.5) * w_ + 1)));
    const int j0 = std::max(0, static_cast<int>(std::floor(lo.y / H_ * h_ - 1)));
    const int j1 = std::min(h_ - 1, static_cast<int>(std::ceil(hi.y / H_ * h_ + 1)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) f(i, j, at(i, j));
  }

  void over(int i, int j, Rgb c, double a) {
    if (a <= 0) return;
    a = std::min(a, 1.0);
    const std::size_t k = static_cast<std::size_t>(j) * w_ + i;
    rgb_[3 * k] = c.r * a + rgb_[3 * k] * (1 - a);
    rgb_[3 * k + 1] = c.g * a + rgb_[3 * k + 1] * (1 - a);
    rgb_[3 * k + 2] = c.b * a + rgb_[3 * k + 2] * (1 - a);
    a_[k] = a + a_[k] * (1 - a);
  }

  // A capsule from a (radius ra) to b (radius rb), coloured by `colour(t)` with t in [0, 1]
  // along it. Radii below half a pixel are drawn half a pixel wide: a needle or a thin stem is a
  // one-texel line, as it is seen from the distance a texel spans (its leaf area is counted at
  // its true size elsewhere).
  template <class C>
  void capsule(P2 a, P2 b, double ra, double rb, C&& colour) {
    const double rmax = std::max({ra, rb, 0.5 * px_});
    const P2 lo{std::min(a.x, b.x) - rmax, std::min(a.y, b.y) - rmax};
    const P2 hi{std::max(a.x, b.x) + rmax, std::max(a.y, b.y) + rmax};
    const P2 ab = b - a;
    const double l2 = std::max(dot(ab, ab), 1e-18);
    each(lo, hi, [&](int i, int j, P2 p) {
      const double t = std::clamp(dot(p - a, ab) / l2, 0.0, 1.0);
      const double r = ra + (rb - ra) * t;
      const double d = len(p - (a + ab * t));
      const double rd = std::max(r, 0.5 * px_);
      const double cov = std::clamp((rd - d) / px_ + 0.5, 0.0, 1.0);
      over(i, j, colour(t), cov);
    });
  }

  // Straight-alpha RGBA bytes into `img` at (ox, oy); transparent texels take `fill`.
  void write(Rgba8& img, int ox, int oy, Rgb fill) const {
    for (int j = 0; j < h_; ++j)
      for (int i = 0; i < w_; ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * w_ + i;
        const double a = a_[k];
        Rgb c = fill;
        if (a >= 1.0 / 255) c = {rgb_[3 * k] / a, rgb_[3 * k + 1] / a, rgb_[3 * k + 2] / a};
        std::uint8_t* px = &img.pixels[(static_cast<std::size_t>(oy + j) * img.width + ox + i) * 4];
        auto byte = [](double v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5); };
        px[0] = byte(c.r);
        px[1] = byte(c.g);
        px[2] = byte(c.b);
        px[3] = byte(a);
      }
  }

 private:
  int w_, h_;
  double W_, H_, px_;
  std::vector<double> rgb_, a_;
};

// A leaf blade with its base at `base`, axis at `angle` from +y, length l, full width w, the
// species silhouette; returns its area (m^2), integrated from the outline.
double blade(Cell& cell, P2 base, double angle, double l, double w, LeafShape shape, const LeafVariant& lv,
             const LeafLook& look, double tint) {
  const P2 u = unit_at(angle), v{u.y, -u.x};
  double area = 0;
  constexpr int kSteps = 256;
  for (int s = 0; s < kSteps; ++s) area += blade_half_width(shape, (s + 0.5) / kSteps, lv);
  area *= 2 * (w / 2) * l / kSteps;
  const P2 tip = base + u * l;
  const double r = w / 2 + cell.pixel_m();
  const P2 lo{std::min(base.x, tip.x) - r, std::min(base.y, tip.y) - r};
  const P2 hi{std::max(base.x, tip.x) + r, std::max(base.y, tip.y) + r};
  const double px = cell.pixel_m();
  cell.each(lo, hi, [&](int i, int j, P2 p) {
    const P2 d = p - base;
    const double a = dot(d, u), b = dot(d, v);
    const double tau = a / l;
    if (tau <= 0 || tau >= 1) return;
    const double half = blade_half_width(shape, tau, lv) * w / 2;
    if (half <= 0) return;
    const double cov = std::clamp((half - std::abs(b)) / px + 0.5, 0.0, 1.0);
    if (cov <= 0) return;
    const double rel = std::abs(b) / half;
    double vein = std::clamp(1 - std::abs(b) / (0.035 * w + 0.5 * px), 0.0, 1.0);
    const double lateral = std::abs(std::fmod(tau * 7 - rel * 1.2 + 10, 1.0) - 0.5);
    if (shape != LeafShape::kNeedle)
      vein = std::max(vein, 0.45 * std::clamp(1 - lateral / 0.06, 0.0, 1.0) * (1 - rel));
    const double fold = b > 0 ? 1.08 : 0.9;  // a folded blade: one half lighter
    const double margin = 1 - 0.15 * std::clamp((rel - 0.6) / 0.4, 0.0, 1.0);
    cell.over(i, j, scaled(mix(look.color, look.vein, vein), tint * fold * margin), cov);
  });
  return area;
}

// Keeps a leaf (base, angle, length) inside the cell's margins: turns it towards the stem and
// shortens it a little until its tip and widest point fit.
void fit_leaf(const Cell& cell, P2 base, double& angle, double& l, double w, double stem_angle) {
  const double xm = cell.width() * (0.5 - kMargin), y0 = cell.height() * kMargin,
               y1 = cell.height() * (1 - kMargin);
  for (int k = 0; k < 24; ++k) {
    const P2 u = unit_at(angle);
    const P2 tip = base + u * l;
    const P2 mid = base + u * (0.55 * l);
    const P2 v{u.y, -u.x};
    bool ok = true;
    for (const P2 p : {tip, mid + v * (w / 2), mid - v * (w / 2)})
      if (std::abs(p.x) > xm || p.y < y0 || p.y > y1) ok = false;
    if (ok) return;
    angle = stem_angle + 0.85 * (angle - stem_angle);
    l *= 0.96;
  }
}

// The stem: a quadratic Bézier from the top edge's middle towards the tip, as `n` capsules.
struct Stem {
  P2 p0, p1, p2;
  P2 at(double t) const { return p0 * ((1 - t) * (1 - t)) + p1 * (2 * (1 - t) * t) + p2 * (t * t); }
  double angle_at(double t) const {
    const P2 d = (p1 - p0) * (2 * (1 - t)) + (p2 - p1) * (2 * t);
    return std::atan2(d.x, d.y);
  }
};

void draw_stem(Cell& cell, const Stem& s, double r0, double r1, Rgb c0, Rgb c1, double t0 = 0,
               double t1 = 1) {
  constexpr int kPieces = 16;
  for (int k = 0; k < kPieces; ++k) {
    const double ta = t0 + (t1 - t0) * k / kPieces, tb = t0 + (t1 - t0) * (k + 1) / kPieces;
    const double ra = r0 + (r1 - r0) * ta, rb = r0 + (r1 - r0) * tb;
    cell.capsule(s.at(ta), s.at(tb), ra, rb, [&](double t) {
      const double f = ta + (tb - ta) * t;
      return Rgb{c0.r + (c1.r - c0.r) * f, c0.g + (c1.g - c0.g) * f, c0.b + (c1.b - c0.b) * f};
    });
  }
}

Stem make_stem(const Cell& cell, Rng& rng, double reach) {
  const double H = cell.height(), W = cell.width();
  Stem s;
  s.p0 = {0, 0};
  s.p2 = {W * 0.06 * rng.signed_unit(), H * reach};
  s.p1 = {W * 0.10 * rng.signed_unit(), H * reach * 0.5};
  return s;
}

// Side shoots off `main` (alternating, at 30–50°), their ends kept inside the cell.
std::vector<Stem> side_shoots(const Cell& cell, const Stem& main, int count, double reach, double keep,
                              Rng& rng) {
  std::vector<Stem> axes;
  const double H = cell.height();
  for (int k = 0; k < count; ++k) {
    const double t = 0.22 + 0.5 * (k + 0.3 + 0.4 * rng.uniform()) / count;
    const double side = (k % 2 == 0 ? 1.0 : -1.0);
    const double a = main.angle_at(t) + side * (30 + 20 * rng.uniform()) * kPi / 180;
    const double l = H * reach * (0.8 + 0.4 * rng.uniform());
    Stem s;
    s.p0 = main.at(t);
    s.p2 = s.p0 + unit_at(a) * l;
    const double xm = cell.width() * (0.5 - kMargin) - keep;
    s.p2.x = std::clamp(s.p2.x, -xm, xm);
    s.p2.y = std::clamp(s.p2.y, s.p0.y, H * (1 - kMargin) - keep);
    s.p1 = (s.p0 + s.p2) * 0.5 + P2{0.08 * l * rng.signed_unit(), 0.03 * l};
    axes.push_back(s);
  }
  return axes;
}

double axis_length(const Stem& s) {
  double l = 0;
  for (int k = 0; k < 8; ++k) l += len(s.at((k + 1) / 8.0) - s.at(k / 8.0));
  return l;
}

// How many of `n` elements (leaves, needles) each axis carries: in proportion to its length
// (axis_length), rounded, and at least `at_least`.
std::vector<int> per_axis(const std::vector<Stem>& axes, int n, int at_least) {
  std::vector<double> lengths;
  double total = 0;
  for (const Stem& s : axes) total += lengths.emplace_back(axis_length(s));
  std::vector<int> counts;
  for (const double l : lengths)
    counts.push_back(std::max(at_least, static_cast<int>(std::lround(n * l / total))));
  return counts;
}

// A twig with side shoots and leaves; returns the leaf area drawn (m^2).
double draw_twig(Cell& cell, const CardLook& card, const LeafLook& leaf, const BarkLook& bark, Rng& rng) {
  const double keep = 0.5 * card.leaf_length_m;
  const Stem main = make_stem(cell, rng, std::max(0.4, 1 - kMargin - keep / cell.height()));
  std::vector<Stem> axes{main};
  for (const Stem& s : side_shoots(cell, main, card.shoots, 0.42, keep, rng)) axes.push_back(s);
  const Rgb twig0 = mix(bark.color, bark.dark, 0.45), twig1 = mix(leaf.vein, bark.color, 0.5);
  const double r0 = std::max(0.0035, 1.2 * cell.pixel_m()), r1 = std::max(0.0012, 0.6 * cell.pixel_m());
  for (std::size_t k = 0; k < axes.size(); ++k)
    draw_stem(cell, axes[k], k == 0 ? r0 : 0.7 * r0, r1, twig0, twig1);
  struct LeafDraw {
    P2 stalk, base;
    double angle, l, w, tint;
    LeafVariant lv;
  };
  std::vector<LeafDraw> leaves;
  const int n = std::max(1, card.elements + static_cast<int>(rng.below(3)) - 1);
  const std::vector<int> counts = per_axis(axes, n, 1);
  const double leaf_w_full = card.leaf_length_m * card.leaf_width;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const Stem& axis = axes[k];
    // Leaves on this axis in proportion to its length; one of them terminal.
    const int m = counts[k];
    for (int i = 0; i < m; ++i) {
      const bool terminal = i == m - 1;
      double t = 1.0;
      if (!terminal) {
        const double u = std::clamp((i + 0.5 + 0.3 * rng.signed_unit()) / m, 0.0, 1.0);
        t = (k == 0 ? 0.1 : 0.15) + 0.85 * (1 - std::pow(1 - u, 1 + 2.5 * card.cluster));
      }
      const double side = ((i + k) % 2 == 0 ? 1.0 : -1.0);
      const double sa = axis.angle_at(t);
      double angle = terminal ? sa + 0.15 * rng.signed_unit()
                              : sa + side * (card.leaf_angle_deg + 15 * rng.signed_unit()) * kPi / 180;
      const double size = terminal ? 1.0 : 0.8 + 0.25 * rng.uniform();
      double l = card.leaf_length_m * size;
      const double fore = terminal ? 0.95 : 0.75 + 0.25 * rng.uniform();  // leaves seen at an angle
      const double w = leaf_w_full * size * fore;
      LeafDraw d;
      d.lv.width = rng.uniform(0.85, 1.0);
      d.lv.phase = rng.uniform(0, 0.5);
      d.lv.lobes = rng.uniform(3.5, 5.0);
      d.tint = rng.uniform(0.85, 1.12);
      const P2 at = axis.at(t);
      fit_leaf(cell, at + unit_at(angle) * (card.petiole * l), angle, l, w, sa);
      d.stalk = at;
      d.base = at + unit_at(angle) * (card.petiole * l);
      d.angle = angle;
      d.l = l;
      d.w = w;
      leaves.push_back(d);
    }
  }
  // Petioles first (under the blades), then the blades.
  for (const LeafDraw& d : leaves)
    cell.capsule(d.stalk, d.base, std::max(0.0012, 0.5 * cell.pixel_m()),
                 std::max(0.0008, 0.4 * cell.pixel_m()),
                 [&](double) { return scaled(mix(leaf.vein, bark.color, 0.3), 0.85); });
  double area = 0;
  for (const LeafDraw& d : leaves)
    area += blade(cell, d.base, d.angle, d.l, d.w, leaf.shape, d.lv, leaf, d.tint);
  return area;
}

// A needle: a capsule of diameter `dia`, from dark green at the base to a lighter tip; its
// area is length x diameter.
double needle(Cell& cell, P2 a, double angle, double l, double dia, const LeafLook& leaf, double tint) {
  const P2 b = a + unit_at(angle) * l;
  cell.capsule(a, b, dia / 2, dia / 3,
               [&](double t) { return scaled(mix(leaf.color, leaf.vein, 0.35 * t), tint); });
  return l * dia;
}

// A needle of a radial brush seen from the card's front: it leaves the axis (direction
// `axis_angle` in the card) at the cone angle `theta` and azimuth `phi` around it, so its
// projection points at atan2(sin theta cos phi, cos theta) from the axis and is shortened to
// sqrt(cos^2 theta + sin^2 theta cos^2 phi) of its length (a needle pointing at the viewer is a dot).
struct Projected {
  double angle, length;
};
Projected brush_needle(double axis_angle, double theta, double phi, double l) {
  const double along = std::cos(theta), across = std::sin(theta) * std::cos(phi);
  return {axis_angle + std::atan2(across, along), l * std::sqrt(along * along + across * across)};
}

// A pine branchlet: a stem with `shoots` side shoots, each axis carrying a bristly bottle brush
// of needles on its distal 38 % (denser towards the tip) — needles all round the axis at the
// preset's angle ± 15° forward, drawn as their projection (brush_needle) — and ending in a
// starburst (30 % of them) radiating up to 80° around the tip; grey-brown twig stems. The
// needle's projected area counts.
double draw_tuft(Cell& cell, const CardLook& card, const LeafLook& leaf, const BarkLook& bark, Rng& rng) {
  const double H = cell.height();
  const double nl = card.leaf_length_m, dia = std::max(card.leaf_length_m * card.leaf_width, 1e-4);
  const Stem main = make_stem(cell, rng, std::max(0.3, 1 - kMargin - 0.9 * nl / H));
  std::vector<Stem> axes{main};
  for (const Stem& s : side_shoots(cell, main, card.shoots, 0.4, 0.9 * nl, rng)) axes.push_back(s);
  // Twig stems grey-brown (the orange bark is the trunk's and the limbs').
  for (std::size_t k = 0; k < axes.size(); ++k)
    draw_stem(cell, axes[k], std::max(0.003, (k == 0 ? 1.2 : 0.9) * cell.pixel_m()),
              std::max(0.0015, 0.7 * cell.pixel_m()), mix(bark.dark, leaf.color, 0.3),
              mix(bark.dark, leaf.color, 0.5));
  double area = 0;
  const std::vector<int> counts = per_axis(axes, std::max(8, card.elements), 8);
  const double theta0 = card.leaf_angle_deg * kPi / 180;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const int m = counts[k];
    for (int i = 0; i < m; ++i) {
      const bool burst = i >= m * 70 / 100;  // the terminal starburst
      const double t = burst ? 1.0 : 0.62 + 0.38 * std::sqrt(rng.uniform());
      const double sa = axes[k].angle_at(t);
      const double theta = burst ? (80 * kPi / 180) * std::sqrt(rng.uniform())
                                 : std::clamp(theta0 + (15 * kPi / 180) * rng.signed_unit(), 0.1, 1.5);
      const double phi = 2 * kPi * rng.uniform();
      const Projected pr = brush_needle(sa, theta, phi, nl * (0.85 + 0.3 * rng.uniform()));
      double angle = pr.angle, l = pr.length;
      const P2 at = axes[k].at(t);
      fit_leaf(cell, at, angle, l, dia, sa);
      area += needle(cell, at, angle, l, dia, leaf, rng.uniform(0.8, 1.15));
    }
  }
  return area;
}

double draw_spray(Cell& cell, const CardLook& card, const LeafLook& leaf, const BarkLook& bark, Rng& rng) {
  const double H = cell.height();
  const double nl = card.leaf_length_m, dia = std::max(card.leaf_length_m * card.leaf_width, 1e-4);
  const Stem main = make_stem(cell, rng, 1 - kMargin - 0.5 * nl / H);
  std::vector<Stem> axes{main};
  // A frond: side shoots at regular steps along the main axis, alternating, shorter towards the
  // tip (a spruce spray's triangular outline).
  const int shoots = std::max(2, card.shoots);
  const double xm = cell.width() * (0.5 - kMargin) - 0.6 * nl;
  for (int k = 0; k < shoots; ++k) {
    const double t = 0.12 + 0.78 * (k + 0.3 * rng.uniform()) / shoots;
    const double side = (k % 2 == 0 ? 1.0 : -1.0);
    const double a = main.angle_at(t) + side * (45 + 15 * rng.uniform()) * kPi / 180;
    const double l = H * 0.45 * (1 - 0.65 * t) * (0.85 + 0.3 * rng.uniform());
    Stem sh;
    sh.p0 = main.at(t);
    sh.p2 = sh.p0 + unit_at(a) * l;
    sh.p2.x = std::clamp(sh.p2.x, -xm, xm);
    sh.p2.y = std::clamp(sh.p2.y, sh.p0.y, H * (1 - kMargin) - 0.6 * nl);
    sh.p1 = (sh.p0 + sh.p2) * 0.5 + P2{0, 0.04 * l};
    axes.push_back(sh);
  }
  for (std::size_t k = 0; k < axes.size(); ++k)
    draw_stem(cell, axes[k], std::max(0.0025, (k == 0 ? 1.1 : 0.8) * cell.pixel_m()),
              std::max(0.001, 0.5 * cell.pixel_m()), mix(bark.color, bark.dark, 0.3),
              mix(bark.color, leaf.vein, 0.4));
  // Needles spread over the axes by their length.
  double area = 0;
  const std::vector<int> counts = per_axis(axes, std::max(8, card.elements), 2);
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const int m = counts[k];
    for (int i = 0; i < m; ++i) {
      const double t = (i + 0.5 * rng.uniform()) / m;
      const double sa = axes[k].angle_at(t);
      const double theta = (card.leaf_angle_deg + 12 * rng.signed_unit()) * kPi / 180;
      const Projected pr =
          brush_needle(sa, theta, 2 * kPi * rng.uniform(), nl * (0.85 + 0.25 * rng.uniform()));
      double angle = pr.angle, l = pr.length;
      const P2 at = axes[k].at(t);
      fit_leaf(cell, at, angle, l, dia, sa);
      area += needle(cell, at, angle, l, dia, leaf, rng.uniform(0.85, 1.12));
    }
  }
  return area;
}

}  // namespace

CardAtlas make_card_atlas(const CardLook& card, const LeafLook& leaf, const BarkLook& bark, int size,
                          Rng& rng) {
  if (size < 16 || size > 8192 || (size & (size - 1)) != 0)
    throw std::invalid_argument("texture size must be a power of two in [16, 8192]");
  CardAtlas atlas;
  atlas.image = {size, size, std::vector<std::uint8_t>(static_cast<std::size_t>(size) * size * 4)};
  const int cw = size / kCardAtlasColumns, ch = size / kCardAtlasRows;
  const double H = card.length_m, W = card.aspect * card.length_m;
  // Colours are composited as the sRGB values the preset gives (as textures.cpp does).
  const LeafLook& lin = leaf;
  for (int v = 0; v < kCardAtlasColumns * kCardAtlasRows; ++v) {
    Cell cell(cw, ch, W, H);
    double area = 0;
    switch (card.style) {
      case CardStyle::kTwig:
        area = draw_twig(cell, card, lin, bark, rng);
        break;
      case CardStyle::kTuft:
        area = draw_tuft(cell, card, lin, bark, rng);
        break;
      case CardStyle::kSpray:
        area = draw_spray(cell, card, lin, bark, rng);
        break;
    }
    atlas.coverage.push_back(static_cast<float>(std::clamp(area / (W * H), 0.0, 1.0)));
    const Rgb fill = scaled(mix(leaf.color, leaf.vein, 0.15), 0.95);
    cell.write(atlas.image, (v % kCardAtlasColumns) * cw, (v / kCardAtlasColumns) * ch, fill);
  }
  return atlas;
}

}  // namespace sylva::generate
