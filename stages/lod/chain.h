// The LOD chain: from a camera and a pixel error to a ladder of spatial errors, and from a tree
// to one simplified model per level.
//
// Seeds: Zhang et al. 2017, §3 (permitted pixel error delta, permitted spatial error epsilon),
// §5.4 (E1 = E2 = E3 = E4 = epsilon per level in the paper), §6 (N <= 8 levels, coarsest
// epsilon 0.22 m); the LOD error model (docs/lod-model.md, libs/lodmodel): s(d) = 2 d tan(phi/2) / H_px,
// epsilon = delta s(d), switch distance d = epsilon / (delta s(1)).
//
// Per level the budgets are E_i = factor_i * epsilon (docs/stages/lod.md explains the defaults:
// E1 = E2 = epsilon/4 and E4 = epsilon/2, so a point of the full-detail branch surface is within
// max(E1 + E2, E1 + E2 + E4) <= epsilon of the simplified skeleton surface, plus E3 for the
// polygonisation).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "libs/lodmodel/lod_model.h"
#include "libs/tree/tree.h"
#include "stages/lod/card_clusters.h"
#include "stages/lod/card_coverage.h"
#include "stages/lod/foliage.h"
#include "stages/lod/internodes.h"
#include "stages/lod/needles.h"
#include "stages/lod/polygonize.h"

namespace sylva::lod {

struct ChainOptions {
  lodmodel::Camera camera;     // the camera the levels' switch distances are for
  double pixel_error = 0.5;    // delta, px
  int levels = 6;              // N, 1..8, used when `errors` is empty
  std::vector<double> errors;  // explicit epsilon per level (m), increasing; overrides N
  double min_error = 0.001;    // epsilon of level 0 (m)
  double max_error = 0.22;     // epsilon of the coarsest level (m), Zhang §6
  double e1 = 0.25, e2 = 0.25, e3 = 1.0, e4 = 0.5, e5 = 1.0;  // factors of epsilon
  double torsion_limit = 1.0471975511965976;                  // Γ (rad), 60°
  int max_edges = 12;                                         // H, >= 3
  bool topology = true;                                       // E4 branch decimation
  bool foliage = true;                                        // leaf collapse (FSA) and needle merging (E5)
  // kappa: a level's cards may also be the card clusters' cut at spread <= kappa pixels at its
  // switch distance (card_clusters.h), used where it has fewer cards than FSA's; 0 = off.
  double card_cluster_px = 0.0;
  // sigma: ... and only cards whose half-diagonal is at most sigma pixels there are clustered.
  double card_size_px = 1.5;
  // The clusters weigh each card by its atlas variant's opacity alpha_v (card_coverage.h): one
  // value per atlas cell (the stage measures them on the tree's atlas); empty = the tree's
  // cell_coverage (tree.h), or 1 without it.
  std::vector<double> card_opacity;
  // A cluster cut is used only when its drawn coverage (card_coverage.h) drifts by at most this
  // fraction from FSA's cut of the same level, else the level keeps FSA's cut; 0 = no check.
  double card_coverage_check = 0.0;
  // The largest linear scale a cluster's survivor may be enlarged by (cluster_cut); 0 = no cap.
  double card_max_scale = 0.0;
  // Cluster the cards that share one placement (a crossed pair: card_places()) as one unit,
  // whose survivor is drawn as all its cards (card_clusters.h "Places"); false = card by card.
  bool card_places = false;
  std::uint64_t card_seed = 0;  // draws the clusters' survivors (the stage: StageContext::rng)
  // Called between branches and inside long merges (may be empty); may throw to stop the chain
  // (the stage passes StageContext::check_cancelled). Called from several threads at once.
  std::function<void()> check_cancelled;
};

struct LevelSpec {
  double epsilon = 0;                             // m
  double delta = 0;                               // px
  double switch_distance = 0;                     // m
  double e1 = 0, e2 = 0, e3 = 0, e4 = 0, e5 = 0;  // m
};

// The epsilon ladder: `errors` when given, else N values geometric from min_error to
// max_error (one level: max_error). Throws std::invalid_argument for a bad ladder.
std::vector<LevelSpec> plan_levels(const ChainOptions& options);

struct LevelCounts {
  std::size_t quads = 0, triangles = 0, lines = 0;  // branches
  std::size_t leaves = 0;                           // leaf quads
  std::size_t needle_lines = 0, needle_quads = 0;   // needles (3 lines, or a triangular prism)
  std::size_t internodes = 0;                       // internodes after merging and decimation
  std::size_t branches = 0;                         // branches kept after decimation
  std::size_t total() const { return quads + triangles + lines + leaves + needle_lines + needle_quads; }
};

// How a level's cards were chosen (card clusters, chain.cpp).
struct CardChoice {
  bool clustered = false;  // the level draws the card clusters' cut (else FSA's)
  std::size_t cut = 0;     // cards of the clusters' cut (0 when not evaluated)
  std::size_t split = 0;   // clusters split for card_max_scale
  bool measured = false;   // drift measured: where the clusters' cut has fewer cards than FSA's
  double drift = 0;        // coverage_drift against FSA's cut (signed; card_coverage.h)
  bool rejected = false;   // fewer cards than FSA's, but |drift| exceeded card_coverage_check
};

struct Level {
  LevelSpec spec;
  BranchGeometry branches;
  BranchGeometry needles;  // needles drawn like internodes (lines or prisms)
  LeafGeometry leaves;
  double line_alpha_eq12 = 1;  // length-weighted mean of eq. 12 over the branch line internodes
  double line_alpha = 1;  // drawn alpha of each branch line: lodmodel::drawn_line_alpha(eq. 12 mean, delta)
  double needle_alpha_eq12 = 1;  // the same for needle lines
  double needle_line_alpha = 1;
  LevelCounts counts;
  CardChoice cards;
  std::vector<std::vector<std::uint32_t>> kept_nodes;  // per branch; empty = decimated
  // An imported tree's level 0 and full detail: the user's own model (tree.source), drawn as the
  // file had it instead of the geometry above (which is then empty). Non-owning: points into the
  // tree the level was built from, which must outlive it. docs/stages/lod.md "Imported trees".
  const tree::SourceGeometry* source = nullptr;
};

// The level that draws `tree`'s source geometry with the numbers of `spec` (an imported tree's
// model is within any epsilon of itself): counts.triangles is the model's triangle count, line
// alphas 1, no branches, leaves or needles of its own. Throws std::invalid_argument when the
// tree has no source geometry.
Level source_level(const tree::Tree& tree, const LevelSpec& spec);

// Data computed once per tree and shared by every level.
struct Precomputed {
  std::vector<BranchSkeleton> skeletons;
  std::vector<double> accumulated;   // A(b), topology.h
  std::vector<double> subtree_area;  // side-on area of each branch's subtree, m^2 (topology.h)
  LeafForest leaf_forest;
  CardForest card_forest;  // built when card_cluster_px > 0
  NeedleForest needle_forest;
  std::vector<char> card_twigs;  // per branch: drawn by its twig/shoot cards, so not drawn as bark
};

Precomputed precompute(const tree::Tree& tree, const ChainOptions& options);

// One level from the precomputed data (the three passes of Zhang §3: merging, topology,
// polygonisation; then foliage).
Level build_level(const tree::Tree& tree, const Precomputed& pre, const LevelSpec& spec,
                  const ChainOptions& options);

// The full-detail model the levels are measured against (`sylva lodcheck`): epsilon = 0, so no
// merging (except exactly collinear runs of equal radius), no decimation, every polygon with
// max_edges sides, every leaf and needle. Its switch distance is 0.
Level build_full_detail(const tree::Tree& tree, const Precomputed& pre, const ChainOptions& options);

// Every level of plan_levels(options).
std::vector<Level> build_chain(const tree::Tree& tree, const ChainOptions& options);
// The same from data precompute(tree, options) made (the stage also builds the full detail from it).
std::vector<Level> build_chain(const tree::Tree& tree, const Precomputed& pre, const ChainOptions& options);

}  // namespace sylva::lod
