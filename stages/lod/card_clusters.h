// Card clustering for the coarse levels: stratified, coverage-preserving pruning of aggregate
// detail.
//
// Seeds: Cook, Halstead, Planck, Ryu 2007, "Stochastic simplification of aggregate detail"
// (SIGGRAPH, ACM TOG 26(3) 79): when many small elements (leaves) fall into few pixels, draw a
// subset of them and scale the survivors so that the total area — hence the expected pixel
// coverage — is kept, with the pruned fraction set by the elements' size on screen; Remolar et
// al. (FSA/VDF, seed 004) §3–4: the leaf (four vertices) is the unit, a sequence of collapses
// recorded once as a binary forest and cut per level. docs/stages/lod.md ("Card clusters").
//
// Our criterion (the papers name the idea, not these definitions):
//   * Every card i carries its drawn area W_i = alpha_i A_i: its quad area A_i times alpha_i, the
//     measured opaque fraction of its atlas variant's cell (the stage measures it on the atlas
//     it draws, alpha >= the MASK cutoff; card_opacity()). Cook et al. preserve the elements'
//     area because area is what they draw; an alpha-masked card draws alpha A, and variants
//     differ (a sparse needle shoot against a dense one), so the clusters preserve W, not A.
//   * A binary forest over the leaf quads (cards) by greedy agglomeration (pair_merge.h): a
//     cluster z of cards has the drawn-area-weighted centroid c_z of its cards' centres and the
//     spread r_z, an upper bound of the distance from c_z to any of its cards' centres:
//       c_z = (W_a c_a + W_b c_b) / (W_a + W_b),
//       r_z = max(|c_z - c_a| + r_a, |c_z - c_b| + r_b)    (r = 0 for one card)     [m]
//     and the pair of lowest r_z merges first. err(z) = max(r_z, h_z), h_z the largest
//     half-diagonal of its cards (monotone towards the roots): cards are clustered only where
//     they are themselves small on screen (Cook et al. prune where elements are small), so the
//     orientation a cluster's survivor imposes on its cards (crossed cards become one) is not
//     resolved.
//   * A level of spatial error epsilon and pixel error delta is seen from its switch distance,
//     where a pixel measures s = epsilon / delta metres (docs/lod-model.md). Its cards are the cut of the
//     forest at err <= kappa s (kappa = `card_cluster_px`): every card's coverage moves by at most
//     kappa pixels, the aggregate-detail counterpart of the branches' delta-pixel bound.
//   * Each cluster of the cut is drawn as ONE card (Cook's survivor, FSA's four-vertex unit): the
//     survivor, a member drawn with probability proportional to its drawn area W (Cook's random
//     pruning; at each merge a's survivor with probability W_a / (W_a + W_b), from a hash of the
//     seed and the two survivors' ids, so no orientation — no layer of crossed cards — is
//     favoured), moved to c_z and scaled about its centre to the area
//       A_z = rho_z (sum_i W_i) / alpha_s,
//     so that it draws the sum of its cards' drawn areas (Cook's area preservation, in drawn
//     area) times the cluster's overlap ratio rho_z = sum_v U_v / sum_v S_v over 7 directions v
//     (the 3 axes and the 4 body diagonals), U_v what the cards projected along v draw together
//     and S_v the sum of what each draws, both counted on the same 16 x 16 raster of the
//     cluster's projected box: a cell under cards i draws 1 - prod_i (1 - alpha_i) of itself
//     in U_v (their alpha masks taken as independent) and sum_i alpha_i in S_v. rho = 1 for
//     cards that do not overlap; overlapping cards (a conifer shoot cluster) keep what they draw
//     together, not the sum, which over-covers. With every alpha 1 this is the area-preserving
//     cluster of opaque cards (A_z = rho sum A_i, U_v the union of the projected cards).
//   * The survivor's linear scale sqrt(A_z / A_s) may be capped (`card_max_scale`): a cut cluster
//     whose survivor would grow more is replaced by its two children, recursively (cluster_cut),
//     so no single card stands for a patch of crown far larger than itself.
//   The survivor keeps its normal, uvs (its own whole atlas cell) and winding.
//   * Places (`card_places`, lod v9). The generator emits a place's layers — a crossed pair of
//     cards, or three — as cards with one base point, direction, length and width, rolled apart
//     about their common axis (stages/generate/foliage_placement.cpp; the .sylt records only the
//     cards). Clustered card by card, the layers of one place merge first (spread 0) into one
//     flat survivor, and the cut replaces an isotropic crossed pair by a single quad of one
//     orientation. With places, the forest's original elements are places (card_places(): cards
//     with bit-identical branch, position, direction, length and width), not cards: a place's W
//     is the sum of its cards' drawn areas, c its W-weighted centre, r the largest distance from
//     c to its cards' centres (0 for exact pairs), h the largest half-diagonal; the cluster's
//     survivor is the place of the heaviest W among its places (ties: lowest id; no draw), and
//     it is drawn as all its cards, moved together to c_z and scaled by one factor k about their
//     centre so that they draw what the cluster's cards draw:
//       k^2 = rho_z sum_i W_i / (rho_s W_s),
//     rho_s the overlap ratio of the survivor place's own cards (a crossed pair covers less
//     than the sum of its two cards from most directions, and so does each of the cluster's
//     pairs; rho_s = 1 for a place of one card, which is the card rule above). The survivor is
//     a crossed pair again, with the heaviest place's orientation.
// Clustering is a choice between two cuts per level (chain.cpp): the one with fewer cards, and
// with `card_coverage_check` only when its drawn coverage stays within that tolerance of FSA's
// cut (card_coverage.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "stages/lod/foliage.h"
#include "stages/lod/pair_merge.h"

namespace sylva::lod {

struct CardCluster {
  tree::Vec3 centroid;         // drawn-area-weighted mean of the cards' centres, m
  double spread = 0;           // upper bound of |centroid - card centre| over the cards, m
  double area = 0;             // sum of the cards' quad areas, m^2
  double drawn = 0;            // sum of the cards' drawn areas W = alpha A, m^2
  double size = 0;             // largest half-diagonal of its cards, m
  std::uint32_t survivor = 0;  // id of the original element (card, or place) drawn for the cluster
  double survivor_drawn = 0;   // the survivor's own drawn area W_s, m^2
};

struct CardForest {
  std::vector<LeafQuad> cards;  // the original cards (leaf_quad of each tree leaf)
  std::vector<double> opacity;  // alpha per original card, in [0, 1]
  // The forest's original elements: the cards of each (ids into `cards`, ascending); without
  // places one element per card, element i = {i}.
  std::vector<std::vector<std::uint32_t>> places;
  std::vector<CardCluster> clusters;  // one per element: originals, then one per merge
  BinaryForest forest;                // error = max(spread, size) of the merged elements
};

// The places of a tree's cards (file comment): cards with bit-identical branch, position,
// direction, length and width form one place, whatever their order in `leaves`; places are
// ordered by their first card, each place's cards ascending. Every card is in exactly one place
// (a card that shares its placement with none is a place of one card).
std::vector<std::vector<std::uint32_t>> card_places(std::span<const tree::Leaf> leaves);

// The cluster forest of `cards` (deterministic: ties on ids, pair_merge.h; survivors drawn from
// `seed`). `opacity`: alpha per card (empty = 1 for every card, the area-preserving clusters;
// else one value in [0, 1] per card, else std::invalid_argument). `size_weight` w =
// kappa / sigma: a merged element's error is max(r_z, w h_z), so the cut at kappa s keeps
// clusters with spread <= kappa s whose cards are at most sigma s (half-diagonal). `places`
// (card_places(); empty = every card its own element): the original elements clustered as units
// (file comment; the survivor is then the heaviest place, `seed` unused); every card must lie in
// exactly one non-empty place, else std::invalid_argument.
CardForest build_card_forest(std::vector<LeafQuad> cards, std::vector<double> opacity = {},
                             std::uint64_t seed = 0, double size_weight = 1.0,
                             std::vector<std::vector<std::uint32_t>> places = {});

// rho (file comment) of the cards `members` (ids into cards), in (0, 1]; 1 for one card or
// cards with no projected area. With `opacity` (alpha per card of `cards`, empty = 1) each
// raster cell counts what its cards' masks draw together, 1 - prod (1 - alpha_i) (independent
// masks), against sum alpha_i: two coincident opaque cards have rho = 1/2, two of alpha 1/2
// have rho = 3/4.
double overlap_ratio(std::span<const LeafQuad> cards, std::span<const std::uint32_t> members,
                     std::span<const double> opacity = {});

// The cards drawn for element `id` of the forest, appended to `out` (and their alphas to
// `alpha` when given): an original element's own cards, else the survivor's cards moved to the
// centroid and scaled about their centre by k (file comment: a card survivor to rho * drawn /
// alpha_s). Returns k, the survivor's linear scale (1 for an original element).
double cluster_cards(const CardForest& forest, std::uint32_t id, std::vector<LeafQuad>& out,
                     std::vector<double>* alpha = nullptr);

// The one card drawn for element `id` (cluster_cards) of a forest whose survivor is one card;
// std::invalid_argument for a survivor place of several cards. `scale`, when given, receives
// the survivor's linear scale sqrt(A_z / A_s) (1 for a single card).
LeafQuad cluster_card(const CardForest& forest, std::uint32_t id, double* scale = nullptr);

struct ClusterCut {
  std::vector<LeafQuad> cards;  // the cards of each cluster of the cut (one per card survivor)
  std::vector<double> opacity;  // the survivor's alpha per card
  std::size_t split = 0;        // clusters replaced by their children for card_max_scale
};

// The cards of a level: the cut at err <= max_error (m), one survivor (a card, or a place's
// cards) per cluster; a cluster whose survivor's scale exceeds `max_scale` (> 0; 0 = no cap) is
// replaced by its children, recursively (original elements are never scaled). Ordered by the
// cut's ascending ids, each split cluster's children in its place.
ClusterCut cluster_cut(const CardForest& forest, double max_error, double max_scale = 0);

}  // namespace sylva::lod
