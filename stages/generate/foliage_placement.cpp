// Foliage placement on the last branch level (foliage_placement.h states the rules and seeds).
#include "stages/generate/foliage_placement.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "libs/tree/foliage.h"
#include "libs/tree/frames.h"

namespace sylva::generate {

namespace {

using tree::Vec3;

constexpr double kPi = std::numbers::pi;
constexpr double kGolden = 2.399963229728653;  // rad, 137.5°: phyllotaxy
constexpr Vec3 kUp{0, 1, 0};
constexpr double kCardOverlap = 0.2;  // fraction of a card overlapped by the next one on a twig

// One branch's polyline with arc lengths and rotation-minimising frames, to evaluate the axis
// point, radius, tangent and normal at an arc length.
struct Axis {
  const tree::Branch* branch = nullptr;
  std::vector<double> s;            // arc length at each node
  std::vector<tree::Frame> frames;  // per node
  double length() const { return s.back(); }

  struct Point {
    Vec3 p, t, n;
    double r;
  };
  Point at(double x) const {
    const auto& nodes = branch->nodes;
    const std::size_t last = nodes.size() - 1;
    std::size_t k = static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), x) - s.begin());
    k = std::clamp<std::size_t>(k, 1, last) - 1;  // segment k .. k + 1
    const double len = s[k + 1] - s[k];
    const double f = len > 0 ? std::clamp((x - s[k]) / len, 0.0, 1.0) : 0.0;
    Point q;
    q.p = nodes[k].position + (nodes[k + 1].position - nodes[k].position) * f;
    q.r = nodes[k].radius + (nodes[k + 1].radius - nodes[k].radius) * f;
    const Vec3 seg = nodes[k + 1].position - nodes[k].position;
    q.t = tree::length(seg) > 0 ? tree::normalized(seg) : frames[k].t;
    q.n = tree::normalized(frames[k].n - q.t * tree::dot(frames[k].n, q.t));
    if (tree::length(q.n) < 0.5) q.n = frames[k].b;
    return q;
  }
};

std::vector<Axis> make_axes(const tree::Tree& tree, std::span<const std::uint32_t> ids) {
  std::vector<Axis> axes;
  axes.reserve(ids.size());
  for (std::uint32_t id : ids) {
    Axis a;
    a.branch = &tree.branches[id];
    const auto& nodes = a.branch->nodes;
    a.s.resize(nodes.size());
    for (std::size_t k = 1; k < nodes.size(); ++k)
      a.s[k] = a.s[k - 1] + tree::length(nodes[k].position - nodes[k - 1].position);
    a.frames = tree::compute_frames(nodes, kUp);
    axes.push_back(std::move(a));
  }
  return axes;
}

// Elements per branch in proportion to the zone lengths (largest remainder, ties by order).
std::vector<std::uint64_t> share(const std::vector<double>& lengths, std::uint64_t total) {
  std::vector<std::uint64_t> count(lengths.size(), 0);
  double sum = 0;
  for (double l : lengths) sum += l;
  if (sum <= 0 || total == 0) return count;
  std::vector<std::pair<double, std::size_t>> rem;
  std::uint64_t given = 0;
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    const double exact = static_cast<double>(total) * lengths[i] / sum;
    count[i] = static_cast<std::uint64_t>(std::floor(exact));
    given += count[i];
    rem.push_back({exact - std::floor(exact), i});
  }
  std::stable_sort(rem.begin(), rem.end(), [](auto& a, auto& b) { return a.first > b.first; });
  for (std::size_t k = 0; given < total && k < rem.size(); ++k, ++given) ++count[rem[k].second];
  return count;
}

struct Placed {
  std::vector<tree::Leaf> leaves;
  std::vector<tree::Needle> needles;
};

// Single leaves or needles: five draws per element (azimuth, angle, size, twist, variant).
Placed place_single(const std::vector<Axis>& axes, std::span<const std::uint32_t> ids,
                    const FoliageSpec& spec, std::uint64_t total, Rng& rng) {
  Placed out;
  std::vector<double> zone(axes.size());
  for (std::size_t i = 0; i < axes.size(); ++i) zone[i] = axes[i].length() * spec.zone;
  const std::vector<std::uint64_t> count = share(zone, total);
  const unsigned cells = static_cast<unsigned>(spec.materials.atlas_cells());
  const bool needles = spec.mode == FoliageSpec::Mode::kNeedles;
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const Axis& a = axes[i];
    const double z0 = a.length() - zone[i];
    double azimuth = 0;
    for (std::uint64_t j = 0; j < count[i]; ++j) {
      const double x = z0 + (static_cast<double>(j) + 0.5) * zone[i] / static_cast<double>(count[i]);
      azimuth += spec.rotate + spec.rotate_v * rng.signed_unit();
      const double angle =
          std::clamp(spec.natural_angle + spec.down_angle_v * rng.signed_unit(), 0.05, kPi - 0.05);
      const double size = 1 + 0.15 * rng.signed_unit();
      const double twist = 0.3 * rng.signed_unit();
      const auto variant = static_cast<std::uint8_t>(rng.below(cells));
      const Axis::Point q = a.at(x);
      const Vec3 o = q.n * std::cos(azimuth) + tree::cross(q.t, q.n) * std::sin(azimuth);
      const Vec3 base = q.p + o * q.r;
      Vec3 dir = tree::normalized(q.t * std::cos(angle) + o * std::sin(angle));
      const double length = spec.leaf_scale * size;
      if ((base + dir * length).y < 0)
        dir = tree::normalized(Vec3{dir.x, std::abs(dir.y), dir.z});  // above ground
      if (needles) {
        tree::Needle n;
        n.branch = ids[i];
        n.base = tree::to_float(base);
        n.tip = tree::to_float(base + dir * length);
        n.radius = static_cast<float>(std::max(length * spec.leaf_scale_x / 2, 1e-5));
        out.needles.push_back(n);
        continue;
      }
      // The blade faces the sky, tilted towards the outside of the branch by the twist.
      const Vec3 up = kUp - dir * tree::dot(kUp, dir);
      const Vec3 side = o - dir * tree::dot(o, dir);
      Vec3 n = up * (0.7 + twist) + side * (0.3 - twist);
      if (tree::length(n) < 1e-6) n = tree::cross(dir, q.n);
      n = tree::normalized(n - dir * tree::dot(n, dir));
      tree::Leaf l;
      l.branch = ids[i];
      l.position = tree::to_float(base);
      l.direction = tree::to_float(dir);
      l.normal = tree::to_float(n);
      l.length = static_cast<float>(length);
      l.width = static_cast<float>(length * spec.leaf_scale_x);
      l.variant = variant;
      out.leaves.push_back(l);
    }
  }
  return out;
}

double wrap_pi(double a) { return a - 2 * kPi * std::floor((a + kPi) / (2 * kPi)); }

// Unit vector orthogonal to d (deterministic).
Vec3 any_perpendicular(Vec3 d) {
  const Vec3 h = std::abs(d.y) < 0.9 ? kUp : Vec3{1, 0, 0};
  return tree::normalized(tree::cross(d, h));
}

// Cards tiling each branch's zone from the tip back; per place two draws (position jitter,
// size) and per layer two (roll jitter, variant).
Placed place_cards(const std::vector<Axis>& axes, std::span<const std::uint32_t> ids, const FoliageSpec& spec,
                   double k, int layers, double density, Rng& rng) {
  Placed out;
  const CardShape& c = spec.card;
  const double len = k * c.length;
  const double step = (1 - kCardOverlap) * len;
  const unsigned cells = static_cast<unsigned>(spec.materials.atlas_cells());
  const double spread = 1 - std::clamp(c.light_bias, 0.0, 1.0);
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const Axis& a = axes[i];
    const double L = a.length();
    if (!(L > 0)) continue;
    const double z0 = L * (1 - spec.zone);
    std::vector<double> bases;
    if (L - z0 <= len) {
      bases.push_back(std::max(0.0, L - len));
    } else {
      for (double b = L - len; b > z0 - 0.5 * step; b -= step) bases.push_back(std::max(b, z0));
    }
    for (std::size_t j = 0; j < bases.size(); ++j) {
      const double keep = rng.uniform();  // with density < 1 a place keeps its cards if keep < density
      const double jitter = 0.1 * step * rng.signed_unit();
      const double size = 1 + 0.08 * rng.signed_unit();
      const double sb = std::clamp(bases[j] + (j == 0 ? 0.0 : jitter), 0.0, L);
      const double lc = len * size;
      const Axis::Point q0 = a.at(sb);
      const Axis::Point q1 = a.at(std::min(sb + lc, L));
      Vec3 dir = q1.p - q0.p;
      dir = tree::length(dir) > 1e-6 * lc ? tree::normalized(dir) : q0.t;
      if (q0.p.y + dir.y * lc < 0.01) {  // a card hanging from a low twig: tilt it up off the ground
        const double want = std::clamp((0.01 - q0.p.y) / lc, -1.0, 1.0);
        Vec3 h{dir.x, 0, dir.z};
        h = tree::length(h) > 1e-9 ? tree::normalized(h) : Vec3{1, 0, 0};
        dir = tree::normalized(h * std::sqrt(1 - want * want) + kUp * want);
      }
      // The light: up and away from the trunk's axis.
      Vec3 out_h{q0.p.x, 0, q0.p.z};
      if (tree::length(out_h) < 1e-6) out_h = Vec3{dir.x, 0, dir.z};
      out_h = tree::length(out_h) < 1e-6 ? Vec3{1, 0, 0} : tree::normalized(out_h);
      const Vec3 light = tree::normalized(kUp + out_h);
      Vec3 n0 = light - dir * tree::dot(dir, light);
      if (tree::length(n0) < 1e-3) n0 = out_h - dir * tree::dot(dir, out_h);
      n0 = tree::length(n0) < 1e-3 ? any_perpendicular(dir) : tree::normalized(n0);
      const Vec3 b0 = tree::cross(dir, n0);
      const double phyllo = spread * wrap_pi(kGolden * static_cast<double>(j + 3 * i));
      for (int m = 0; m < layers; ++m) {
        const double roll = phyllo + (15.0 * kPi / 180) * rng.signed_unit() + kPi * m / layers;
        const auto variant = static_cast<std::uint8_t>(rng.below(cells));
        if (keep >= density) continue;
        Vec3 n = tree::normalized(n0 * std::cos(roll) + b0 * std::sin(roll));
        const double w = c.aspect * lc;
        // Keep the card's edges above the ground: near it, turn the card flat (side horizontal).
        const Vec3 side = tree::cross(n, dir) * (0.5 * w);
        if (std::min(q0.p.y, q0.p.y + dir.y * lc) - std::abs(side.y) < 0.005) {
          const Vec3 h = tree::cross(dir, kUp);
          if (tree::length(h) > 1e-6) n = tree::normalized(tree::cross(tree::normalized(h), dir));
          if (n.y < 0) n = -n;
        }
        tree::Leaf l;
        l.branch = ids[i];
        l.position = tree::to_float(q0.p);
        l.direction = tree::to_float(dir);
        l.normal = tree::to_float(n);
        l.length = static_cast<float>(lc);
        l.width = static_cast<float>(w);
        l.variant = variant;
        out.leaves.push_back(l);
      }
    }
  }
  return out;
}

double lai_of(tree::Tree& t, Placed& p) {
  std::swap(t.leaves, p.leaves);
  std::swap(t.needles, p.needles);
  const double lai = tree::crown_foliage(t).lai();
  std::swap(t.leaves, p.leaves);
  std::swap(t.needles, p.needles);
  return lai;
}

}  // namespace

FoliageResult place_foliage(tree::Tree& tree, std::span<const std::uint32_t> ids, const FoliageSpec& spec,
                            Rng& rng) {
  FoliageResult res;
  tree.materials = spec.materials;
  const std::vector<Axis> axes = make_axes(tree, ids);
  const Rng start = rng;
  Placed placed;
  if (spec.mode == FoliageSpec::Mode::kCards) {
    // The leaf area scales with k (cards along a twig: count 1/k, area k^2) and with the density
    // of places; below kMinCardScale the density falls instead of the leaves shrinking.
    int layers = std::max(1, spec.card.min_layers);
    double k = 1, density = 1;
    auto run = [&] {
      Rng r = start;
      placed = place_cards(axes, ids, spec, k, layers, density, r);
      rng = r;
    };
    auto rescale = [&](double f) {
      const double a = std::min(k * density * f, kMaxCardScale);
      if (a >= kMinCardScale) {
        k = a;
        density = 1;
      } else {
        k = kMinCardScale;
        density = a / kMinCardScale;
      }
    };
    run();
    if (spec.target_lai > 0) {
      const double lai = lai_of(tree, placed);
      if (lai > 0) {
        // The fewest layers (the fewest cards) whose scale stays at most kPreferredCardScale.
        const double per_layer = lai / layers;
        const int lo = std::max(1, spec.card.min_layers), hi = std::max(lo, spec.card.max_layers);
        for (layers = lo; layers < hi && spec.target_lai / (per_layer * layers) > kPreferredCardScale;
             ++layers) {
        }
        rescale(spec.target_lai / (per_layer * layers));
        // Refine; keep the closest (the crown's hull moves a little with every placement).
        double best_k = k, best_density = density, best_error = INFINITY;
        for (int refine = 0; refine < 5; ++refine) {
          run();
          const double now = lai_of(tree, placed);
          if (!(now > 0)) break;
          if (std::abs(now - spec.target_lai) < best_error) {
            best_error = std::abs(now - spec.target_lai);
            best_k = k;
            best_density = density;
          }
          rescale(spec.target_lai / now);
        }
        k = best_k;
        density = best_density;
        run();
      }
    }
    res.card_scale = k;
    res.layers = layers;
    res.density = density;
  } else {
    double count = spec.count > 0 ? std::floor(spec.count + 0.5) : 2000.0;
    auto run = [&] {
      Rng r = start;
      placed = place_single(axes, ids, spec, static_cast<std::uint64_t>(count), r);
      rng = r;
    };
    run();
    if (spec.target_lai > 0) {
      for (int refine = 0; refine < 2; ++refine) {
        const double now = lai_of(tree, placed);
        if (!(now > 0)) break;
        count = std::min(5e6, std::max(1.0, std::floor(count * spec.target_lai / now + 0.5)));
        run();
      }
    }
  }
  res.elements = placed.leaves.size() + placed.needles.size();
  tree.leaves = std::move(placed.leaves);
  tree.needles = std::move(placed.needles);
  res.lai = tree::crown_foliage(tree).lai();
  return res;
}

}  // namespace sylva::generate
