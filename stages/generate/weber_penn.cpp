// Weber & Penn (1995) parametric trees with Nystad's (2010) natural rules.
//
// Nystad 2010: Appendix A (parameters), §3.1 + Appendix B (da Vinci radii, Murray angles, child
// offset eq. 3.5), §4.1 (process outline), §4.2.1–4.2.2 (intermediate nodes, 10 % skip rule),
// §5.2.1 (primary deviation through parent-relative transforms), §5.2.2 (breadth-first, one
// PRNG), §4.3.2 (maximum node spacing). Weber & Penn 1995: shape ratio, taper/flare, child
// counts and lengths, curve/curve-back, rotate, attraction up.
//
// The generator runs in three passes, mirroring the thesis's process outline; one file each, and
// the records they hand on in weber_penn_passes.h:
//   1. Growth (weber_penn_growth.cpp; the only pass that draws random numbers for the branches):
//      breadth-first by level, every branch's length, segments, curve, splits and lateral
//      children, then the hem heights of the last level. Nothing here depends on world
//      positions, so a level's draws never depend on deeper ones.
//   2. Structure (weber_penn_structure.cpp): per branch, in parent-first order, the nodes in
//      arc-length space — segment nodes, split stubs, prepended/appended intermediate nodes
//      around every attachment (with the 10 % skip rule), spacing nodes — and their radii: W&P
//      taper between nodes, exact da Vinci steps at every junction.
//   3. World (weber_penn_world.cpp): per branch, in parent-first order, walk the nodes carrying a
//      frame (direction and side); curve and attraction turn it at segment nodes; at junctions
//      the children's frames are taken and then the primary deviation (Murray's angle for the
//      primary) turns the rest of the branch — and with it every later child — which is exactly
//      the thesis's parent-relative propagation, in one O(nodes) pass. Then the foliage on the
//      last level, from the same Rng (foliage_placement.h).
#include "stages/generate/weber_penn.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "stages/generate/weber_penn_passes.h"

namespace sylva::generate {

namespace weber_penn {

const LevelParams& level_params(const Preset& p, std::size_t level) {
  return p.level[std::min(level, p.level.size() - 1)];
}

}  // namespace weber_penn

double shape_ratio(int shape, double r) {
  switch (shape) {
    case 0:
      return 0.2 + 0.8 * r;  // conical
    case 1:
      return 0.2 + 0.8 * std::sin(std::numbers::pi * r);  // spherical
    case 2:
      return 0.2 + 0.8 * std::sin(0.5 * std::numbers::pi * r);  // hemispherical
    case 3:
      return 1.0;  // cylindrical
    case 4:
      return 0.5 + 0.5 * r;  // tapered cylindrical
    case 5:
      return r <= 0.7 ? r / 0.7 : (1 - r) / 0.3;  // flame
    case 6:
      return 1 - 0.8 * r;  // inverse conical
    case 7:
      return r <= 0.7 ? 0.5 + 0.5 * r / 0.7 : 0.5 + 0.5 * (1 - r) / 0.3;  // tend flame
    default:
      return 1.0;
  }
}

void validate_preset(const Preset& p) {
  auto need = [](bool ok, const std::string& key, const std::string& rule) {
    if (!ok) throw PresetError(key, key + " must be " + rule);
  };
  need(p.shape >= 0 && p.shape <= 7, "Shape", "0..7");
  need(p.levels >= 1 && p.levels <= 8, "Levels", "1..8");
  need(p.scale > 0 && p.scale <= 200, "Scale", "in (0, 200]");
  need(p.scale_v >= 0 && p.scale_v < p.scale, "ScaleV", "in [0, Scale)");
  need(p.base_size >= 0 && p.base_size < 1, "BaseSize", "in [0, 1)");
  need(p.ratio > 0 && p.ratio < 1, "Ratio", "in (0, 1)");
  need(p.flare >= 0 && p.flare <= 10, "Flare", "in [0, 10]");
  need(p.base_splits >= 0 && p.base_splits <= 8, "BaseSplits", "0..8");
  need(std::abs(p.attraction_up) <= 10, "AttractionUp", "in [-10, 10]");
  need(p.tree_shape_exponent >= 1.5 && p.tree_shape_exponent <= 4, "TreeShapeExponent", "in [1.5, 4]");
  need(p.leaves >= 0 && p.leaves <= 5e6, "Leaves", "in [0, 5000000]");
  need(p.leaf_scale > 0 && p.leaf_scale <= 2, "LeafScale", "in (0, 2]");
  need(p.leaf_scale_x > 0 && p.leaf_scale_x <= 4, "LeafScaleX", "in (0, 4]");
  need(p.leaf_area_index >= 0 && p.leaf_area_index <= 20, "LeafAreaIndex", "in [0, 20]");
  need(p.foliage_zone > 0 && p.foliage_zone <= 1, "FoliageZone", "in (0, 1]");
  need(p.card_scale >= 0.25 && p.card_scale <= 4, "CardScale", "in [0.25, 4]");
  need(p.hem >= 0 && p.hem < 1, "Hem", "in [0, 1)");
  need(p.hem_v >= 0 && p.hem_v < 1, "HemV", "in [0, 1)");
  need(p.trunk_up >= 0 && p.trunk_up <= 1, "TrunkUp", "in [0, 1]");
  need(p.shape_floor >= 0 && p.shape_floor <= 1, "ShapeFloor", "in [0, 1]");
  need(p.pendulous >= 0 && p.pendulous <= 1, "Pendulous", "in [0, 1]");
  need(p.pendulous == 0 || p.attraction_up < 0, "Pendulous", "0 unless AttractionUp < 0");
  need(p.shape_floor == kWeberPennShapeFloor || p.shape <= 2, "ShapeFloor",
       "0.2 (W&P's) unless Shape is 0, 1 or 2");
  need(p.card.length > 0 && p.card.length <= 5, "card.length_m", "in (0, 5]");
  need(p.card.aspect > 0 && p.card.aspect <= 4, "card.aspect", "in (0, 4]");
  need(p.card.min_layers >= 1 && p.card.min_layers <= p.card.max_layers && p.card.max_layers <= 4,
       "card.layers", "[min, max] with 1 <= min <= max <= 4");
  need(p.card.light_bias >= 0 && p.card.light_bias <= 1, "card.light_bias", "in [0, 1]");
  need(p.bark_tint_from >= 0 && p.bark_tint_from <= p.bark_tint_to && p.bark_tint_to <= 1,
       "textures.bark.lower_tint", "heights 0 <= below <= above <= 1 (fractions of the tree's height)");
  need(!p.level.empty(), "levels", "a list with at least the trunk");
  for (std::size_t i = 0; i < p.level.size(); ++i) {
    const LevelParams& l = p.level[i];
    const std::string at = "levels[" + std::to_string(i) + "].";
    need(l.branches >= 0 && l.branches <= 10000, at + "Branches", "in [0, 10000]");
    need(l.length > 0 && l.length <= 100, at + "Length", "in (0, 100]");
    need(l.length_v >= 0 && l.length_v < l.length, at + "LengthV", "in [0, Length)");
    need(l.taper >= 0 && l.taper <= 3, at + "Taper", "in [0, 3]");
    need(l.seg_splits >= 0 && l.seg_splits <= 4, at + "SegSplits", "in [0, 4]");
    need(l.split_angle_v >= 0 && l.split_angle_v <= 90, at + "SplitAngleV", "in [0, 90]");
    need(l.curve_res >= 1 && l.curve_res <= 100, at + "CurveRes", "1..100");
    need(std::abs(l.curve) <= 720, at + "Curve", "in [-720, 720]");
    need(std::abs(l.curve_back) <= 720, at + "CurveBack", "in [-720, 720]");
    need(l.curve_v >= 0 && l.curve_v <= 720, at + "CurveV", "in [0, 720]");
    need(std::abs(l.down_angle_v) <= 180, at + "DownAngleV", "in [-180, 180]");
    need(std::abs(l.rotate) <= 360, at + "Rotate", "in [-360, 360]");
    need(l.rotate_v >= 0 && l.rotate_v <= 360, at + "RotateV", "in [0, 360]");
    need(l.branch_ratio > 0 && l.branch_ratio <= 1, at + "BranchRatio", "in (0, 1]");
    need(l.clumps >= 0 && l.clumps <= 100, at + "Clumps", "0..100");
    need(l.clump_size > 0 && l.clump_size <= 1, at + "ClumpSize", "in (0, 1]");
    need(l.clump_base >= 0 && l.clump_base < 1, at + "ClumpBase", "in [0, 1)");
  }
  need(std::abs(p.leaf.down_angle_v) <= 180, "leaf.DownAngleV", "in [-180, 180]");
  need(std::abs(p.leaf.rotate) <= 360, "leaf.Rotate", "in [-360, 360]");
  need(p.leaf.rotate_v >= 0 && p.leaf.rotate_v <= 360, "leaf.RotateV", "in [0, 360]");
  need(p.leaf.branch_ratio > 0 && p.leaf.branch_ratio <= 1, "leaf.BranchRatio", "in (0, 1]");
}

tree::Tree generate_tree(const Preset& preset, const GenerateOptions& options, Rng& rng) {
  validate_preset(preset);
  if (options.levels < 0 || options.levels > 8) throw std::invalid_argument("levels must be 0..8");
  if (!(options.max_node_spacing >= 0)) throw std::invalid_argument("max_node_spacing must be >= 0");
  if (!(options.leaf_density >= 0)) throw std::invalid_argument("leaf_density must be >= 0");
  // 1. Growth: every random draw of the branches.
  weber_penn::Growth growth =
      weber_penn::grow(preset, options.levels > 0 ? options.levels : preset.levels, rng);
  // 2. Structure: nodes and radii in arc-length space.
  const weber_penn::Structure structure = weber_penn::build_structure(preset, options, growth);
  // 3. World: positions and frames, then the foliage.
  tree::Tree t;
  t.name = options.name;
  t.materials = preset.materials;
  weber_penn::place_branches(preset, growth, structure, t);
  weber_penn::add_foliage(preset, options, growth.last_level, rng, t);
  return t;
}

}  // namespace sylva::generate
