// Species read as themselves (issue 9): geometric properties of a preset's generated tree that
// its look depends on, each asserted for every age and several seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "libs/tree/stats.h"
#include "stages/generate/tests/species_trees.h"

namespace sylva::generate {
namespace {

using test::generate_with_cards;
using tree::Vec3;

// The four corners of a foliage quad.
std::array<Vec3, 4> corners(const tree::Leaf& l) {
  const Vec3 p = tree::to_double(l.position), d = tree::to_double(l.direction);
  const Vec3 side = tree::cross(tree::to_double(l.normal), d) * (0.5 * l.width);
  return {p - side, p + side, p + d * double(l.length) + side, p + d * double(l.length) - side};
}

double branch_length(const tree::Branch& b) {
  double len = 0;
  for (std::size_t k = 1; k < b.nodes.size(); ++k)
    len += tree::length(b.nodes[k].position - b.nodes[k - 1].position);
  return len;
}

// The weeping willow: a visible trunk under a broad crown, with curtains of pendulous shoots
// hanging from it towards the ground, at the crown's edge rather than filling it. Every age,
// seeds 1-3 and 7: at most 1 % of the foliage's area reaches below 0.15 of the height (the
// issue-9 preset's curtains swept the ground: 12-16 %; now at most 0.02 %), at least 35 % of it
// below half the height (now 39-44 %), at most 30 % of it within 0.3 of the crown's radius of the
// trunk's vertical (the issue-9 preset's ball: 34-49 %; now 15-22 %), at least 1000 hanging
// shoots, the crown at least 0.85 h wide.
TEST(SpeciesLook, WeepingWillowHangsCurtainsAboveAVisibleTrunk) {
  const SpeciesPreset s = load_species_preset("configs/species/weeping_willow.yaml");
  for (const AgeVariant& a : s.ages) {
    for (std::uint64_t seed : {1, 2, 3, 7}) {
      const tree::Tree t = generate_with_cards(s, a, seed);
      const tree::TreeStats st = tree::compute_stats(t);
      const double h = st.height;
      const std::string what = a.age + " seed " + std::to_string(seed);
      // Foliage: its lowest point; the shares of its area reaching below 0.15 and 0.5 of the
      // height, and within 30 % of the crown's radius of the trunk's vertical.
      double lowest = 1e9, radius = 0, area = 0, low_area = 0, inner_area = 0, ground_area = 0;
      for (const tree::Leaf& l : t.leaves)
        radius = std::max(radius, std::hypot(double(l.position.x), double(l.position.z)));
      for (const tree::Leaf& l : t.leaves) {
        double y = 1e9;
        for (const Vec3& q : corners(l)) y = std::min(y, q.y);
        lowest = std::min(lowest, y);
        const double w = double(l.length) * l.width;
        area += w;
        if (y < 0.5 * h) low_area += w;
        if (y < 0.15 * h) ground_area += w;
        if (std::hypot(double(l.position.x), double(l.position.z)) < 0.3 * radius) inner_area += w;
      }
      // Pendulous shoots: last-level branches at least 1 m long whose tip hangs at least half
      // their length below their base and whose last segment points down (within 30°).
      std::uint32_t last = 0;
      for (const tree::Branch& b : t.branches) last = std::max(last, b.level);
      int hanging = 0;
      for (const tree::Branch& b : t.branches) {
        if (b.level != last || b.nodes.size() < 2) continue;
        const double len = branch_length(b);
        const Vec3 tip = b.nodes.back().position, end = tip - b.nodes[b.nodes.size() - 2].position;
        if (len >= 1 && b.nodes.front().position.y - tip.y >= 0.5 * len &&
            end.y < -std::cos(30 * 3.14159265 / 180) * tree::length(end))
          ++hanging;
      }
      const double width = std::min(st.bounds_max.x - st.bounds_min.x, st.bounds_max.z - st.bounds_min.z);
      std::printf(
          "[ willow   ] %s: height %.1f m, foliage from %.2f h, below 0.15 h %.4f, below h/2 %.2f, inner "
          "%.3f, "
          "hanging shoots %d, width %.2f h\n",
          what.c_str(), h, lowest / h, ground_area / area, low_area / area, inner_area / area, hanging,
          width / h);
      EXPECT_LE(ground_area / area, 0.01) << what << ": the curtains hide the trunk";
      EXPECT_GE(low_area / area, 0.35) << what << ": the curtains do not hang towards the ground";
      EXPECT_LE(inner_area / area, 0.3) << what << ": foliage fills the crown (a ball, not curtains)";
      EXPECT_GE(hanging, 1000) << what;
      EXPECT_GE(width, 0.85 * h) << what << ": the crown is not broad";
    }
  }
}

// The columnar white poplar stands upright: every age, seeds 1-3 and 7, the trunk's top lies
// within 3 % of the tree's height of the vertical through its base, and no node of the trunk
// strays further than that (the issue-9 preset leaned 3-21 %: the primary deviations of its 70
// thick level-1 branches added up; now TrunkUp 0.5: at most 0.8 %); the crown is a column (at
// most 0.45 h wide).
TEST(SpeciesLook, WhitePoplarStandsUpright) {
  const SpeciesPreset s = load_species_preset("configs/species/white_poplar.yaml");
  for (const AgeVariant& a : s.ages) {
    for (std::uint64_t seed : {1, 2, 3, 7}) {
      const tree::Tree t = generate_with_cards(s, a, seed);
      const tree::TreeStats st = tree::compute_stats(t);
      const std::string what = a.age + " seed " + std::to_string(seed);
      const tree::Branch& trunk = t.branches[0];
      const Vec3 base = trunk.nodes.front().position;
      double off = 0;
      for (const tree::Node& n : trunk.nodes)
        off = std::max(off, std::hypot(n.position.x - base.x, n.position.z - base.z));
      const Vec3 top = trunk.nodes.back().position;
      const double top_off = std::hypot(top.x - base.x, top.z - base.z);
      const double width = std::max(st.bounds_max.x - st.bounds_min.x, st.bounds_max.z - st.bounds_min.z);
      std::printf(
          "[ poplar   ] %s: height %.1f m, trunk top %.3f h off the vertical, furthest %.3f h, width %.2f "
          "h\n",
          what.c_str(), st.height, top_off / st.height, off / st.height, width / st.height);
      EXPECT_LE(top_off, 0.03 * st.height) << what << ": the poplar leans";
      EXPECT_LE(off, 0.03 * st.height) << what << ": the poplar's trunk strays";
      EXPECT_LE(width, 0.45 * st.height) << what << ": the poplar is not columnar";
    }
  }
}

// The radius of the foliage per height band: `bands` equal bands from the lowest foliage to the
// top; in each, the 95th percentile of the horizontal distance of the cards' corners from the
// vertical through the trunk's base (0 for an empty band).
std::vector<double> band_radii(const tree::Tree& t, int bands) {
  const Vec3 base = t.branches[0].nodes.front().position;
  double lo = 1e9, hi = -1e9;
  for (const tree::Leaf& l : t.leaves)
    for (const Vec3& q : corners(l)) lo = std::min(lo, q.y), hi = std::max(hi, q.y);
  std::vector<std::vector<double>> r(static_cast<std::size_t>(bands));
  for (const tree::Leaf& l : t.leaves)
    for (const Vec3& q : corners(l)) {
      const int b = std::clamp(static_cast<int>((q.y - lo) / (hi - lo) * bands), 0, bands - 1);
      r[static_cast<std::size_t>(b)].push_back(std::hypot(q.x - base.x, q.z - base.z));
    }
  std::vector<double> out;
  for (auto& v : r) {
    if (v.empty()) {
      out.push_back(0);
      continue;
    }
    std::sort(v.begin(), v.end());
    out.push_back(v[static_cast<std::size_t>(0.95 * static_cast<double>(v.size() - 1))]);
  }
  return out;
}

// Spruces are conical at every age, to a point: seeds 1-3 and 7, over tenths of the foliage's
// height the widest band lies in the lower 40 %, above it no band is wider than the one below by
// more than 5 % of the widest, and the top two tenths are at most 0.28 and 0.36 of the widest
// (the issue-9 preset's young spruce, a blunt column of big sprays: 0.34-0.47 and 0.39-0.49;
// W&P's conical shape keeps the top whorls at a fifth of the longest branches: ShapeFloor).
TEST(SpeciesLook, NorwaySpruceIsConicalAtEveryAge) {
  const SpeciesPreset s = load_species_preset("configs/species/norway_spruce.yaml");
  for (const AgeVariant& a : s.ages) {
    for (std::uint64_t seed : {1, 2, 3, 7}) {
      const tree::Tree t = generate_with_cards(s, a, seed);
      const std::string what = a.age + " seed " + std::to_string(seed);
      const std::vector<double> r = band_radii(t, 10);
      const double widest = *std::max_element(r.begin(), r.end());
      const auto w0 = static_cast<std::size_t>(std::max_element(r.begin(), r.end()) - r.begin());
      double growth = 0;
      for (std::size_t b = w0 + 1; b < r.size(); ++b) growth = std::max(growth, r[b] - r[b - 1]);
      std::printf("[ spruce   ] %s: radius per tenth, bottom to top (m):", what.c_str());
      for (double v : r) std::printf(" %.2f", v);
      std::printf("; top %.2f of the widest, largest growth above it %.2f of it\n", r.back() / widest,
                  growth / widest);
      EXPECT_LE(w0, 3u) << what << ": the widest band is not low down";
      for (std::size_t b = w0 + 1; b < r.size(); ++b)
        EXPECT_LE(r[b], r[b - 1] + 0.05 * widest) << what << " band " << b;
      EXPECT_LE(r[9], 0.28 * widest) << what << ": blunt top";
      EXPECT_LE(r[8], 0.36 * widest) << what << ": blunt top";
    }
  }
}

// The silver birch's fine twigs hang: every age, seeds 1-3 and 7, at least 60 % of the last
// level's twigs end at least a third of their length below their base (the birch before issue
// 9's look pass: 35-48 %; now 64-86 %).
TEST(SpeciesLook, BirchTwigsHang) {
  const SpeciesPreset s = load_species_preset("configs/species/birch.yaml");
  for (const AgeVariant& a : s.ages) {
    for (std::uint64_t seed : {1, 2, 3, 7}) {
      const tree::Tree t = generate_with_cards(s, a, seed);
      const std::string what = a.age + " seed " + std::to_string(seed);
      std::uint32_t last = 0;
      for (const tree::Branch& b : t.branches) last = std::max(last, b.level);
      int twigs = 0, hanging = 0;
      for (const tree::Branch& b : t.branches) {
        if (b.level != last || b.nodes.size() < 2) continue;
        ++twigs;
        if (b.nodes.front().position.y - b.nodes.back().position.y >= branch_length(b) / 3) ++hanging;
      }
      std::printf("[ birch    ] %s: %d of %d twigs hang (%.2f)\n", what.c_str(), hanging, twigs,
                  double(hanging) / twigs);
      EXPECT_GE(hanging, 0.6 * twigs) << what;
    }
  }
}

}  // namespace
}  // namespace sylva::generate
