// The LOD chain: epsilon ladder, switch distances, and the per-level passes.
// Seeds: Zhang et al. 2017, §3 (delta, epsilon), §4.4, §5.1–5.5, §6 (N <= 8, 0.22 m);
// Remolar et al. (FSA/VDF) §4 (uniform extraction); the LOD error model, docs/lod-model.md.
#include "stages/lod/chain.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "libs/tree/foliage.h"
#include "stages/lod/topology.h"

namespace sylva::lod {

std::vector<LevelSpec> plan_levels(const ChainOptions& o) {
  if (!(o.camera.fov_y_rad > 0 && o.camera.fov_y_rad < 3.14159) || o.camera.height_px <= 0)
    throw std::invalid_argument("camera: fov must be in (0, 180) degrees and the image height positive");
  if (!(o.pixel_error > 0)) throw std::invalid_argument("pixel_error must be positive");
  if (o.max_edges < 3) throw std::invalid_argument("max_edges must be >= 3");
  std::vector<double> eps = o.errors;
  if (eps.empty()) {
    if (o.levels < 1 || o.levels > 8) throw std::invalid_argument("levels must be in 1..8 (Zhang §6)");
    if (!(o.min_error > 0) || !(o.max_error >= o.min_error))
      throw std::invalid_argument("need 0 < min_error_m <= max_error_m");
    if (o.levels == 1) {
      eps.push_back(o.max_error);
    } else {
      for (int i = 0; i < o.levels; ++i)
        eps.push_back(o.min_error *
                      std::pow(o.max_error / o.min_error, static_cast<double>(i) / (o.levels - 1)));
    }
  }
  if (eps.size() > 8) throw std::invalid_argument("at most 8 levels (Zhang §6)");
  for (std::size_t i = 0; i < eps.size(); ++i) {
    if (!(eps[i] > 0) || !std::isfinite(eps[i]))
      throw std::invalid_argument("errors[" + std::to_string(i) + "] must be a positive number of metres");
    if (i > 0 && !(eps[i] > eps[i - 1]))
      throw std::invalid_argument("errors must increase strictly (errors[" + std::to_string(i) + "])");
  }
  std::vector<LevelSpec> out;
  for (double e : eps) {
    LevelSpec s;
    s.epsilon = e;
    s.delta = o.pixel_error;
    s.switch_distance = lodmodel::switch_distance(o.camera, e, o.pixel_error);
    s.e1 = o.e1 * e;
    s.e2 = o.e2 * e;
    s.e3 = o.e3 * e;
    s.e4 = o.e4 * e;
    s.e5 = o.e5 * e;
    out.push_back(s);
  }
  return out;
}

Precomputed precompute(const tree::Tree& tree, const ChainOptions& options) {
  Precomputed pre;
  pre.skeletons = build_skeletons(tree);
  if (options.foliage) pre.card_twigs = tree::twigs_drawn_by_cards(tree);
  // The three precomputations are independent (each writes its own member): run them side by
  // side. Each is sequential and deterministic, so the result does not depend on the threads.
  tbb::parallel_invoke(
      [&] {
        if (options.topology) {
          const std::vector<double> h = bearer_distances(pre.skeletons);
          pre.accumulated = accumulated_distances(pre.skeletons, h);
          pre.subtree_area = subtree_areas(pre.skeletons, pre.card_twigs);
        } else {
          pre.accumulated.assign(pre.skeletons.size(), std::numeric_limits<double>::infinity());
        }
      },
      [&] {
        if (options.foliage) pre.leaf_forest = build_leaf_forest(tree.leaves, tree.materials);
      },
      [&] {
        if (!options.foliage || !(options.card_cluster_px > 0) || !(options.card_size_px > 0)) return;
        std::vector<LeafQuad> cards;
        std::vector<double> opacity;
        cards.reserve(tree.leaves.size());
        opacity.reserve(tree.leaves.size());
        for (const tree::Leaf& l : tree.leaves) {
          cards.push_back(leaf_quad(l, tree.materials));
          opacity.push_back(
              std::clamp(card_opacity(cards.back(), tree.materials, options.card_opacity), 0.0, 1.0));
        }
        pre.card_forest = build_card_forest(
            std::move(cards), std::move(opacity), options.card_seed,
            options.card_cluster_px / options.card_size_px,
            options.card_places ? card_places(tree.leaves) : std::vector<std::vector<std::uint32_t>>{});
      },
      [&] {
        if (options.foliage) pre.needle_forest = build_needle_forest(tree.needles);
      });
  return pre;
}

Level build_level(const tree::Tree& tree, const Precomputed& pre, const LevelSpec& spec,
                  const ChainOptions& options) {
  Level level;
  level.spec = spec;
  const std::size_t nb = pre.skeletons.size();
  level.kept_nodes.resize(nb);
  const MergeLimits limits{spec.e1, spec.e2, options.torsion_limit};
  // Topology first decides which branches exist (A(b) <= E4 deletes the subtree; §5.3); it is
  // precomputed on the full skeleton, so only the threshold is per level. Merging (§4.4) then
  // runs on the kept branches, and polygonisation (§5.1–5.2) last.
  std::vector<char> kept_branch(nb, 1);
  for (std::size_t i = 0; i < nb; ++i) {
    const std::int32_t p = pre.skeletons[i].parent;
    if ((p >= 0 && !kept_branch[static_cast<std::size_t>(p)]) || pre.accumulated[i] <= spec.e4)
      kept_branch[i] = 0;
    if (i < pre.card_twigs.size() && pre.card_twigs[i]) kept_branch[i] = 0;  // its cards draw it
  }
  // A decimated subtree's coverage is carried onto its kept bearer's line at the attachment
  // (topology.h, carried_alpha): within A(b) <= E4 of the subtree, but on a sub-pixel bearer
  // the subtree's coverage would otherwise be lost (docs/stages/lod.md). A bearer drawn as a
  // polygon is opaque and at least ~delta px wide there, and covers the subtree's pixels itself.
  std::vector<std::vector<std::pair<double, double>>> deposits(nb);
  for (std::size_t i = 0; i < nb; ++i) {
    const std::int32_t p = pre.skeletons[i].parent;
    if (!kept_branch[i] && p >= 0 && kept_branch[static_cast<std::size_t>(p)] && !pre.subtree_area.empty())
      deposits[static_cast<std::size_t>(p)].emplace_back(pre.skeletons[i].attach_arc, pre.subtree_area[i]);
  }
  std::vector<double> extra;
  for (std::size_t i = 0; i < nb; ++i) {
    if (!kept_branch[i]) continue;
    const auto& g = pre.skeletons[i].g;
    if (options.check_cancelled && (i & 255) == 0) options.check_cancelled();
    merge_internodes(g, limits, level.kept_nodes[i], options.check_cancelled);
    extra.clear();
    if (!deposits[i].empty()) extra = carried_alpha(g, level.kept_nodes[i], deposits[i], spec.e3);
    polygonize_branch(g, level.kept_nodes[i], spec.e3, options.max_edges, level.branches, extra);
    level.counts.internodes += level.kept_nodes[i].size() - 1;
    ++level.counts.branches;
  }
  if (options.foliage) {
    // Foliage is cut by its own error (E5) and kept when its branch is decimated: that branch
    // lies within A(b) <= E4 of its bearer's surface, so its leaves hang at most E4 from drawn
    // bark, while deleting them would move canopy by their whole extent (docs/stages/lod.md).
    if (!tree.leaves.empty()) {
      // FSA's cut by E5, or the card clusters' cut at kappa pixels of this level's switch
      // distance (s = epsilon / delta m per pixel there) where that one has fewer cards: each is
      // within its own bound (foliage.h: geometric, card_clusters.h: coverage moved <= kappa px).
      // With card_coverage_check the clusters must also draw what FSA's cut draws, within that
      // fraction, seen at that pixel size (card_coverage.h); else the level keeps FSA's cut.
      const std::vector<std::uint32_t> active = pre.leaf_forest.forest.cut_by_error(spec.e5);
      ClusterCut clustered;
      if (options.card_cluster_px > 0 && spec.epsilon > 0 && spec.delta > 0 &&
          !pre.card_forest.cards.empty()) {
        const double pixel = lodmodel::switch_pixel_size(spec.epsilon, spec.delta);
        // The cut's size bounds the cards it can draw (a split only adds cards): skip the
        // survivors' construction where it cannot win.
        if (pre.card_forest.forest.cut_by_error(options.card_cluster_px * pixel).size() < active.size()) {
          clustered = cluster_cut(pre.card_forest, options.card_cluster_px * pixel, options.card_max_scale);
          level.cards.cut = clustered.cards.size();
          level.cards.split = clustered.split;
        }
        // The drift is measured wherever the clusters would win (reported in lod.json), and
        // judged only with the check on.
        if (!clustered.cards.empty() && clustered.cards.size() < active.size()) {
          std::vector<LeafQuad> fsa;
          std::vector<double> fsa_alpha;
          fsa.reserve(active.size());
          fsa_alpha.reserve(active.size());
          for (std::uint32_t id : active) {
            fsa.push_back(pre.leaf_forest.quads[id]);
            fsa_alpha.push_back(
                std::clamp(card_opacity(fsa.back(), tree.materials, options.card_opacity), 0.0, 1.0));
          }
          level.cards.measured = true;
          level.cards.drift = coverage_drift(clustered.cards, clustered.opacity, fsa, fsa_alpha, pixel);
          level.cards.rejected =
              options.card_coverage_check > 0 && std::abs(level.cards.drift) > options.card_coverage_check;
        }
      }
      if (!clustered.cards.empty() && clustered.cards.size() < active.size() && !level.cards.rejected) {
        level.cards.clustered = true;
        leaf_geometry(clustered.cards, level.leaves);
      } else {
        leaf_geometry(pre.leaf_forest, active, level.leaves);
      }
    }
    if (!tree.needles.empty()) {
      std::vector<std::uint32_t> active = pre.needle_forest.forest.cut_by_error(spec.e5);
      needle_geometry(pre.needle_forest, active, spec.e3, options.max_edges, level.needles);
    }
  }
  level.line_alpha_eq12 = level.branches.level_alpha();
  level.line_alpha = lodmodel::drawn_line_alpha(level.line_alpha_eq12, spec.delta);
  level.needle_alpha_eq12 = level.needles.level_alpha();
  level.needle_line_alpha = lodmodel::drawn_line_alpha(level.needle_alpha_eq12, spec.delta);
  level.counts.quads = level.branches.quads;
  level.counts.triangles = level.branches.triangles;
  level.counts.lines = level.branches.lines;
  level.counts.leaves = level.leaves.leaves;
  level.counts.needle_lines = level.needles.lines;
  level.counts.needle_quads = level.needles.quads + level.needles.triangles;
  return level;
}

Level build_full_detail(const tree::Tree& tree, const Precomputed& pre, const ChainOptions& options) {
  LevelSpec spec;
  spec.delta = options.pixel_error;
  return build_level(tree, pre, spec, options);
}

std::vector<Level> build_chain(const tree::Tree& tree, const ChainOptions& options) {
  return build_chain(tree, precompute(tree, options), options);
}

std::vector<Level> build_chain(const tree::Tree& tree, const Precomputed& pre, const ChainOptions& options) {
  const std::vector<LevelSpec> specs = plan_levels(options);
  // Levels are independent given the precomputed data: one task per level, each into its slot.
  std::vector<Level> out(specs.size());
  tbb::parallel_for(std::size_t{0}, specs.size(),
                    [&](std::size_t i) { out[i] = build_level(tree, pre, specs[i], options); });
  return out;
}

}  // namespace sylva::lod
