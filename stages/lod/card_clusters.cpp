// Card clusters: a coverage-preserving cut of the cards for the coarse levels.
// Seeds: Cook, Halstead, Planck, Ryu 2007, "Stochastic simplification of aggregate detail"
// (prune aggregate detail, scale the survivors to keep the area); Remolar et al. (FSA/VDF) §3–4
// (the four-vertex leaf as the unit, a binary forest cut per level). Definitions: card_clusters.h.
#include "stages/lod/card_clusters.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace sylva::lod {

using tree::Vec3;

namespace {

// The merged cluster's centroid (drawn-area-weighted; the midpoint for two elements that draw
// nothing).
Vec3 merged_centroid(const CardCluster& a, const CardCluster& b) {
  const double w = a.drawn + b.drawn;
  if (!(w > 0)) return (a.centroid + b.centroid) * 0.5;
  return (a.centroid * a.drawn + b.centroid * b.drawn) * (1.0 / w);
}

double merged_spread(const CardCluster& a, const CardCluster& b, const Vec3& c) {
  return std::max(length(c - a.centroid) + a.spread, length(c - b.centroid) + b.spread);
}

struct ClusterMetric {
  CardCluster key(const CardCluster& c) const { return c; }
  Vec3 center(const CardCluster& k) const { return k.centroid; }
  double cost(const CardCluster& a, const CardCluster& b, double /*bound*/) const {
    return merged_spread(a, b, merged_centroid(a, b));
  }
  // The centroid lies on the segment between the two centres, so r_z >= max(|c - c_a|, |c - c_b|)
  // >= d / 2, and r_z >= |c - c_a| + r_a >= r_a. The slack covers rounding.
  double lower_bound(const CardCluster& a, double distance) const {
    return std::max(0.5 * distance, a.spread) - 1e-12;
  }
};

// A uniform number in [0, 1) from (seed, i, j): SplitMix64 (Steele, Lea, Flood 2014) over the
// three words; deterministic and independent of the merge order's threads.
double unit_hash(std::uint64_t seed, std::uint32_t i, std::uint32_t j) {
  std::uint64_t x = seed ^ (static_cast<std::uint64_t>(i) << 32 | j);
  for (int r = 0; r < 2; ++r) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
  }
  return static_cast<double>(x >> 11) * 0x1.0p-53;
}

// Projected quad corners on the plane orthogonal to a direction.
struct Quad2 {
  std::array<double, 8> p;  // x0 y0 x1 y1 ...
};

// Inside a convex quad (either winding), boundary included.
bool inside(const Quad2& q, double x, double y) {
  bool pos = false, neg = false;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const double ex = q.p[2 * j] - q.p[2 * i], ey = q.p[2 * j + 1] - q.p[2 * i + 1];
    const double c = ex * (y - q.p[2 * i + 1]) - ey * (x - q.p[2 * i]);
    pos |= c > 0;
    neg |= c < 0;
    if (pos && neg) return false;
  }
  return true;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> card_places(std::span<const tree::Leaf> leaves) {
  // The generator writes a place's layers with these fields bit for bit equal (the same base,
  // chord and size; only the roll, i.e. the normal, and the variant differ), so exact equality
  // is the test; float bits, so -0 and 0 differ and nothing is rounded together.
  using Key = std::array<std::uint32_t, 9>;
  std::map<Key, std::uint32_t> index;
  std::vector<std::vector<std::uint32_t>> out;
  for (std::uint32_t i = 0; i < leaves.size(); ++i) {
    const tree::Leaf& l = leaves[i];
    const Key key = {l.branch,
                     std::bit_cast<std::uint32_t>(l.position.x),
                     std::bit_cast<std::uint32_t>(l.position.y),
                     std::bit_cast<std::uint32_t>(l.position.z),
                     std::bit_cast<std::uint32_t>(l.direction.x),
                     std::bit_cast<std::uint32_t>(l.direction.y),
                     std::bit_cast<std::uint32_t>(l.direction.z),
                     std::bit_cast<std::uint32_t>(l.length),
                     std::bit_cast<std::uint32_t>(l.width)};
    const auto [it, fresh] = index.emplace(key, static_cast<std::uint32_t>(out.size()));
    if (fresh) out.emplace_back();
    out[it->second].push_back(i);
  }
  return out;
}

CardForest build_card_forest(std::vector<LeafQuad> cards, std::vector<double> opacity, std::uint64_t seed,
                             double size_weight, std::vector<std::vector<std::uint32_t>> places) {
  if (opacity.empty()) opacity.assign(cards.size(), 1.0);
  if (opacity.size() != cards.size())
    throw std::invalid_argument("card clusters: " + std::to_string(opacity.size()) + " opacities for " +
                                std::to_string(cards.size()) + " cards");
  for (double a : opacity)
    if (!(a >= 0 && a <= 1))
      throw std::invalid_argument("card clusters: a card's opacity must lie in [0, 1]");
  const bool by_place = !places.empty();
  if (by_place) {
    std::vector<char> seen(cards.size(), 0);
    for (std::size_t p = 0; p < places.size(); ++p) {
      if (places[p].empty())
        throw std::invalid_argument("card clusters: place " + std::to_string(p) + " has no card");
      for (std::uint32_t c : places[p]) {
        if (c >= cards.size() || seen[c])
          throw std::invalid_argument("card clusters: place " + std::to_string(p) + " names card " +
                                      std::to_string(c) +
                                      (c >= cards.size() ? " of " + std::to_string(cards.size()) + " cards"
                                                         : ", which is in another place too"));
        seen[c] = 1;
      }
    }
    for (std::size_t c = 0; c < cards.size(); ++c)
      if (!seen[c])
        throw std::invalid_argument("card clusters: card " + std::to_string(c) + " is in no place");
  } else {
    places.resize(cards.size());
    for (std::uint32_t i = 0; i < cards.size(); ++i) places[i] = {i};
  }
  CardForest cf;
  cf.cards = std::move(cards);
  cf.opacity = std::move(opacity);
  cf.places = std::move(places);
  cf.clusters.reserve(2 * cf.places.size());
  for (std::uint32_t p = 0; p < cf.places.size(); ++p) {
    const std::vector<std::uint32_t>& members = cf.places[p];
    if (members.size() == 1) {
      const std::uint32_t i = members[0];
      const LeafQuad& q = cf.cards[i];
      double half = 0;
      for (const Vec3& v : q.v) half = std::max(half, length(v - q.center()));
      const double drawn = cf.opacity[i] * q.area;
      cf.clusters.push_back({q.center(), 0.0, q.area, drawn, half, p, drawn});
      continue;
    }
    // A place of several cards: W the sum of its cards' drawn areas, c their W-weighted centre
    // (the plain mean when nothing is drawn), r the largest distance from c to a card's centre.
    CardCluster z;
    Vec3 weighted{0, 0, 0}, plain{0, 0, 0};
    for (std::uint32_t i : members) {
      const LeafQuad& q = cf.cards[i];
      const double w = cf.opacity[i] * q.area;
      weighted = weighted + q.center() * w;
      plain = plain + q.center();
      z.area += q.area;
      z.drawn += w;
      for (const Vec3& v : q.v) z.size = std::max(z.size, length(v - q.center()));
    }
    z.centroid =
        z.drawn > 0 ? weighted * (1.0 / z.drawn) : plain * (1.0 / static_cast<double>(members.size()));
    for (std::uint32_t i : members) z.spread = std::max(z.spread, length(cf.cards[i].center() - z.centroid));
    z.survivor = p;
    z.survivor_drawn = z.drawn;
    cf.clusters.push_back(z);
  }
  cf.forest =
      agglomerate(cf.clusters, ClusterMetric{},
                  [seed, size_weight, by_place](const CardCluster& a, const CardCluster& b, double, double) {
                    CardCluster z;
                    z.centroid = merged_centroid(a, b);
                    z.spread = merged_spread(a, b, z.centroid);
                    z.area = a.area + b.area;
                    z.drawn = a.drawn + b.drawn;
                    z.size = std::max(a.size, b.size);
                    if (by_place) {
                      // Places: the heaviest place survives (ties: the lower id), so the survivor is a
                      // crossed pair in the orientation that drew most of the cluster; no draw.
                      const bool keep_a = a.survivor_drawn > b.survivor_drawn ||
                                          (a.survivor_drawn == b.survivor_drawn && a.survivor < b.survivor);
                      z.survivor = keep_a ? a.survivor : b.survivor;
                    } else {
                      // Cook's random pruning within the cluster: a's survivor with probability
                      // W_a / (W_a + W_b), so every card survives its cluster with probability
                      // proportional to its drawn area (the product telescopes) and no orientation is
                      // favoured (crossed cards' layers alike). Clusters that draw nothing fall back to the
                      // quad areas.
                      const double u = unit_hash(seed, a.survivor, b.survivor);
                      z.survivor = z.drawn > 0  ? (u * z.drawn < a.drawn ? a.survivor : b.survivor)
                                   : z.area > 0 ? (u * z.area < a.area ? a.survivor : b.survivor)
                                                : a.survivor;
                    }
                    z.survivor_drawn = z.survivor == a.survivor ? a.survivor_drawn : b.survivor_drawn;
                    return std::pair<CardCluster, double>(z, std::max(z.spread, size_weight * z.size));
                  });
  return cf;
}

double overlap_ratio(std::span<const LeafQuad> cards, std::span<const std::uint32_t> members,
                     std::span<const double> opacity) {
  if (members.size() < 2) return 1.0;
  constexpr int kGrid = 16;
  const double r3 = 1 / std::sqrt(3.0);
  static constexpr int kDirs = 7;
  const std::array<Vec3, kDirs> dirs = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {r3, r3, r3}, {r3, r3, -r3}, {r3, -r3, r3}, {-r3, r3, r3}}};
  double union_area = 0, sum_area = 0;
  std::vector<Quad2> quads(members.size());
  for (const Vec3& v : dirs) {
    // An orthonormal basis (u, w) of the plane orthogonal to v.
    const Vec3 helper = std::abs(v.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 u = normalized(cross(v, helper));
    const Vec3 w = cross(v, u);
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const LeafQuad& q = cards[members[m]];
      for (int i = 0; i < 4; ++i) {
        const double x = dot(q.v[i], u), y = dot(q.v[i], w);
        quads[m].p[2 * i] = x;
        quads[m].p[2 * i + 1] = y;
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
    }
    if (!(x1 > x0) || !(y1 > y0)) continue;
    const double dx = (x1 - x0) / kGrid, dy = (y1 - y0) / kGrid;
    // Per cell the transmittance prod (1 - alpha_i) of the cards over it: the cell draws
    // 1 - prod, the cards' sum draws sum alpha_i (with every alpha 1: the union and the sum).
    std::array<double, kGrid * kGrid> clear;
    clear.fill(1.0);
    double hits = 0;
    for (std::size_t m = 0; m < quads.size(); ++m) {
      const Quad2& q = quads[m];
      const double alpha = opacity.empty() ? 1.0 : opacity[members[m]];
      double qx0 = q.p[0], qx1 = q.p[0], qy0 = q.p[1], qy1 = q.p[1];
      for (int i = 1; i < 4; ++i) {
        qx0 = std::min(qx0, q.p[2 * i]);
        qx1 = std::max(qx1, q.p[2 * i]);
        qy0 = std::min(qy0, q.p[2 * i + 1]);
        qy1 = std::max(qy1, q.p[2 * i + 1]);
      }
      // Cells whose centre may lie in the quad's box.
      const int i0 = std::max(0, static_cast<int>(std::floor((qx0 - x0) / dx - 0.5)));
      const int i1 = std::min(kGrid - 1, static_cast<int>(std::ceil((qx1 - x0) / dx - 0.5)));
      const int j0 = std::max(0, static_cast<int>(std::floor((qy0 - y0) / dy - 0.5)));
      const int j1 = std::min(kGrid - 1, static_cast<int>(std::ceil((qy1 - y0) / dy - 0.5)));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          if (!inside(q, x0 + (i + 0.5) * dx, y0 + (j + 0.5) * dy)) continue;
          hits += alpha;
          clear[static_cast<std::size_t>(j * kGrid + i)] *= 1 - alpha;
        }
    }
    double drawn = 0;
    for (double c : clear) drawn += 1 - c;
    union_area += drawn * dx * dy;
    sum_area += hits * dx * dy;
  }
  if (!(sum_area > 0)) return 1.0;
  return std::clamp(union_area / sum_area, 0.0, 1.0);
}

double cluster_cards(const CardForest& cf, std::uint32_t id, std::vector<LeafQuad>& out,
                     std::vector<double>* alpha_out) {
  const std::size_t n = cf.forest.original;
  auto emit = [&](const LeafQuad& q, std::uint32_t card) {
    out.push_back(q);
    if (alpha_out) alpha_out->push_back(cf.opacity[card]);
  };
  if (id < n) {
    for (std::uint32_t c : cf.places[id]) emit(cf.cards[c], c);
    return 1.0;
  }
  std::vector<std::uint32_t> members, stack{id};
  while (!stack.empty()) {
    const std::uint32_t e = stack.back();
    stack.pop_back();
    if (e < n) {
      members.insert(members.end(), cf.places[e].begin(), cf.places[e].end());
    } else {
      stack.push_back(static_cast<std::uint32_t>(cf.forest.left[e]));
      stack.push_back(static_cast<std::uint32_t>(cf.forest.right[e]));
    }
  }
  std::sort(members.begin(), members.end());
  const CardCluster& c = cf.clusters[id];
  const std::vector<std::uint32_t>& place = cf.places[c.survivor];
  const double rho = overlap_ratio(cf.cards, members, cf.opacity);
  if (place.size() == 1) {
    const std::uint32_t card = place[0];
    const LeafQuad& s = cf.cards[card];
    // The survivor draws alpha_s A_z = rho sum W_i (card_clusters.h); with nothing drawn (every
    // alpha 0) the quad areas stand in, as they do for the survivor's draw.
    const double alpha = cf.opacity[card];
    const double target = rho * (c.drawn > 0 && alpha > 0 ? c.drawn / alpha : c.area);
    LeafQuad q = s;
    const double k = s.area > 0 ? std::sqrt(target / s.area) : 1.0;
    const Vec3 centre = s.center();
    for (Vec3& v : q.v) v = c.centroid + (v - centre) * k;
    q.area = s.area * k * k;
    emit(q, card);
    return k;
  }
  // A place survives: its cards draw rho_s W_s together, scaled by k they draw k^2 of that, and
  // the cluster's cards drew rho_z sum W_i (card_clusters.h). The quad areas stand in for
  // places that draw nothing.
  const CardCluster& s = cf.clusters[c.survivor];
  const double rho_s = overlap_ratio(cf.cards, place, cf.opacity);
  const double k = c.drawn > 0 && s.drawn > 0 ? std::sqrt(rho * c.drawn / (rho_s * s.drawn))
                   : s.area > 0               ? std::sqrt(rho * c.area / (rho_s * s.area))
                                              : 1.0;
  for (std::uint32_t card : place) {
    LeafQuad q = cf.cards[card];
    for (Vec3& v : q.v) v = c.centroid + (v - s.centroid) * k;
    q.area *= k * k;
    emit(q, card);
  }
  return k;
}

LeafQuad cluster_card(const CardForest& cf, std::uint32_t id, double* scale) {
  const std::uint32_t survivor = id < cf.forest.original ? id : cf.clusters[id].survivor;
  if (cf.places[survivor].size() != 1)
    throw std::invalid_argument("card clusters: element " + std::to_string(id) + " draws a place of " +
                                std::to_string(cf.places[survivor].size()) + " cards, not one card");
  std::vector<LeafQuad> out;
  const double k = cluster_cards(cf, id, out);
  if (scale) *scale = k;
  return out[0];
}

ClusterCut cluster_cut(const CardForest& cf, double max_error, double max_scale) {
  ClusterCut out;
  const std::vector<std::uint32_t> active = cf.forest.cut_by_error(max_error);
  out.cards.reserve(active.size());
  out.opacity.reserve(active.size());
  std::vector<std::uint32_t> stack;
  std::vector<LeafQuad> cards;
  std::vector<double> alpha;
  for (std::uint32_t id : active) {
    stack.assign(1, id);
    while (!stack.empty()) {
      const std::uint32_t e = stack.back();
      stack.pop_back();
      cards.clear();
      alpha.clear();
      const double k = cluster_cards(cf, e, cards, &alpha);
      if (max_scale > 0 && k > max_scale && e >= cf.forest.original) {
        // Right pushed first, so the left child's cards come out first.
        stack.push_back(static_cast<std::uint32_t>(cf.forest.right[e]));
        stack.push_back(static_cast<std::uint32_t>(cf.forest.left[e]));
        ++out.split;
        continue;
      }
      out.cards.insert(out.cards.end(), cards.begin(), cards.end());
      out.opacity.insert(out.opacity.end(), alpha.begin(), alpha.end());
    }
  }
  return out;
}

}  // namespace sylva::lod
