// Foliage on the last branch level: single leaves or needles, or cards (a twig with its leaves,
// or a conifer shoot with its needles), placed so that the crown carries a target leaf area
// index. Pure: a tree with its branches in, the same tree with foliage out; no I/O.
//
// Seeds: Nystad 2010 §5.5.4 and Appendix A.1.1/A.2 (leaves on the last level, the leaf level's
// Rotate/RotateV phyllotaxy, its DownAngleV, LeafScale/LeafScaleX, leaf "type" = texture cell);
// Weber & Penn 1995 (leaves spread along the last level's stems; the blade turned towards the
// light). Bréda 2003 for the leaf area index: one-sided leaf area per unit of (here: crown
// projected) ground area (libs/tree/foliage.h). Card foliage is the games practice ez-tree and
// SpeedTree ship (one alpha-masked quad carrying a twig); the placement rules are ours:
//
//   single  `count` leaves/needles over the foliage zone of every last-level branch (the distal
//           FoliageZone fraction of it), in proportion to the zone's length (largest remainder),
//           evenly spaced; azimuth steps by the leaf level's Rotate ± RotateV (the golden angle
//           137.5° is phyllotaxy); angle from the branch = Murray's y for the leaf level's
//           BranchRatio ± DownAngleV; length LeafScale × (1 ± 15 %); leaf blades face the sky,
//           tilted outwards. Needles: length LeafScale, diameter LeafScale × LeafScaleX.
//   cards   every last-level branch's zone is tiled from its tip back by cards of length
//           k·card.length (each overlapping the next by 20 %), each along the twig's chord so the
//           stem drawn on the card continues the twig, rolled about that chord towards the light
//           (up and away from the trunk, weight card.light_bias) plus a phyllotaxy offset
//           (golden angle, spread 1 − light_bias) and a ±15° jitter; `layers` cards per place,
//           the extra ones rolled by 180°/layers (two layers = crossed cards).
//
// Leaf area index: with a target LAI > 0 the placement is repeated (from the same Rng state, so
// deterministic): single foliage scales its count; cards take the fewest layers (the fewest
// cards) whose scale k stays at most kPreferredCardScale, then k (at most kMaxCardScale) until
// the crown's LAI meets the target (five refinements, the closest kept; within a few per cent).
// Where even kMinCardScale carries too much, the cards thin out instead (density < 1: each place
// keeps its cards with probability `density`, one draw per place whatever the density), so
// leaves never shrink below 85 % of the species' size.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "libs/tree/tree.h"
#include "pipeline/rng.h"

namespace sylva::generate {

inline constexpr double kMinCardScale = 0.85;
inline constexpr double kMaxCardScale = 1.6;
inline constexpr double kPreferredCardScale = 1.3;  // more layers only beyond this scale

struct CardShape {
  double length = 0.4;  // m, along the twig (before the scale k)
  double aspect = 0.8;  // width / length
  int min_layers = 1;   // 2 = always crossed (conifer shoots)
  int max_layers = 3;
  double light_bias = 0.6;  // 0..1: roll towards the light vs phyllotaxy spread
};

struct FoliageSpec {
  enum class Mode { kLeaves, kNeedles, kCards } mode = Mode::kLeaves;
  double target_lai = 0;  // > 0: fit the count (single) or scale (cards) to it
  double count = 0;       // single foliage: elements when target_lai is 0 (or the first guess)
  double zone = 1;        // (0, 1]: distal fraction of each branch that carries foliage
  // Single leaves and needles (Nystad A.1.1 / A.2).
  double leaf_scale = 0.1;  // m
  double leaf_scale_x = 0.5;
  double natural_angle = 0.6;  // rad, Murray's y for the leaf level's BranchRatio
  double down_angle_v = 0;     // rad
  double rotate = 2.4;         // rad
  double rotate_v = 0;         // rad
  // Cards.
  CardShape card;
  tree::Materials materials;  // atlas grid and coverage (leaf area per card)
};

struct FoliageResult {
  double lai = 0;         // crown LAI reached
  double card_scale = 1;  // k (cards)
  int layers = 1;         // cards per place
  double density = 1;     // (0, 1]: places per card length, relative to tiling the twig
  std::size_t elements = 0;
};

// Places the foliage on `branches` (the last level) of `tree` (appending to tree.leaves or
// tree.needles; materials are taken from spec.materials). Draws from `rng` only.
FoliageResult place_foliage(tree::Tree& tree, std::span<const std::uint32_t> branches,
                            const FoliageSpec& spec, Rng& rng);

}  // namespace sylva::generate
