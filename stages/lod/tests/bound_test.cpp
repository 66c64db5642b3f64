// The error bound, checked geometrically on every species preset (young variants, to keep CI
// time small): for every level, every point of the full-detail branch surface (eq. 1) is within
// epsilon of the simplified surface, plus the polygonisation term E3.
//   - kept branches: the merged internode I_{k,q+2} and the original internodes differ linearly
//     in t between nodes, so the largest difference sits at a node; we sample every original
//     node at 16 angles and also mid-internode, and compare with eq. (1) of the merged internode
//     at the same (t, theta): <= phi + varphi <= E1 + E2 (Theorem 2, eq. A6);
//   - decimated branches (with their subtrees): every node's solid is within A(b) <= E4 of the
//     full bearer's solid, which is within E1 + E2 of the simplified bearer;
//   - polygonisation: every ring's edge error R (1 - cos(pi/h)) <= max(E3, R (1 - cos(pi/H)))
//     (eq. 9 clamps h at H), every line R <= E3 / 2.
// Defaults E1 = E2 = epsilon/4, E4 = epsilon/2 make both sums <= epsilon.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "stages/lod/chain.h"
#include "stages/lod/tests/test_trees.h"
#include "stages/lod/topology.h"

namespace sylva::lod {
namespace {

using tree::Vec3;

Vec3 full_point(const std::vector<SkeletalVector>& g, std::size_t k, double u, double theta) {
  return merged_surface_point(g, k, k + 1, u, theta);
}

TEST(ErrorBound, EveryLevelOfEverySpeciesPreset) {
  for (const auto& preset : test::species_presets()) {
    const tree::Tree& t = test::species_tree(preset, "young");
    ChainOptions o;
    o.foliage = false;
    const Precomputed pre = precompute(t, o);
    for (const LevelSpec& spec : plan_levels(o)) {
      const Level level = build_level(t, pre, spec, o);
      const double eps = spec.epsilon;
      double worst_kept = 0, worst_removed = 0;
      for (std::size_t bi = 0; bi < pre.skeletons.size(); ++bi) {
        const auto& g = pre.skeletons[bi].g;
        const auto& kept = level.kept_nodes[bi];
        if (kept.empty()) {
          // Decimated: its own bearer is kept or decimated too (then that one is checked).
          const std::int32_t p = pre.skeletons[bi].parent;
          ASSERT_GE(p, 0);
          if (level.kept_nodes[static_cast<std::size_t>(p)].empty()) continue;
          // Every node of bi's subtree within A(bi) of the full bearer's solid (via bi).
          EXPECT_LE(pre.accumulated[bi], spec.e4);
          for (const SkeletalVector& s : g)
            worst_removed =
                std::max(worst_removed, distance_to_solid(pre.skeletons[static_cast<std::size_t>(p)].g, s.p) +
                                            s.r + spec.e1 + spec.e2);
          continue;
        }
        std::size_t seg = 0;
        for (std::size_t k = 0; k + 1 < g.size(); ++k) {
          while (kept[seg + 1] <= k) ++seg;
          const std::size_t a = kept[seg], b = kept[seg + 1];
          const double span = g[b].arc - g[a].arc;
          for (double u : {0.0, 0.5, 1.0}) {
            const double t_arc = g[k].arc + u * (g[k + 1].arc - g[k].arc);
            const double tau = span > 0 ? (t_arc - g[a].arc) / span : 0.0;
            for (int j = 0; j < 16; ++j) {
              const double theta = 2 * std::numbers::pi * j / 16;
              const double d = length(full_point(g, k, u, theta) - merged_surface_point(g, a, b, tau, theta));
              worst_kept = std::max(worst_kept, d);
            }
          }
        }
      }
      EXPECT_LE(worst_kept, spec.e1 + spec.e2 + 1e-9) << preset.filename() << " eps " << eps;
      EXPECT_LE(worst_kept, eps) << preset.filename();
      EXPECT_LE(worst_removed, eps + 1e-9) << preset.filename() << " eps " << eps;
      // Eq. (9) caps the edge count at H: a ring of radius R has error min over h <= H, so the
      // polygonisation term is max(E3, R_max (1 - cos(pi/H))) (the clamp of the thickest rings).
      double r_max = 0;
      for (const auto& sk : pre.skeletons)
        for (const auto& s : sk.g) r_max = std::max(r_max, s.r);
      const double cap = r_max * (1 - std::cos(std::numbers::pi / o.max_edges));
      EXPECT_LE(level.branches.max_polygon_error, std::max(spec.e3, cap) + 1e-12) << preset.filename();
    }
  }
}

}  // namespace
}  // namespace sylva::lod
