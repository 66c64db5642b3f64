// The parametric tree generator: Weber & Penn's model as Nystad adapts it, with the natural
// rules (da Vinci radii, Murray angles). Pure: a preset, options and a seeded Rng in, a Tree out;
// no I/O.
//
// Seeds: Nystad 2010 — Appendix A (every parameter below), §3.1 and Appendix B (natural rules),
// §4.1–4.2 and §5.2 (process: breadth-first generation, intermediate nodes with the 10 % skip
// rule, primary-deviation pass), §4.3.2 (maximum node spacing); Weber & Penn 1995 for the
// formulas the thesis refers to (shape ratio, taper, flare, child counts and lengths, curve,
// rotate, attraction). docs/stages/generate.md gives each parameter's source and our choices.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/tree/tree.h"
#include "pipeline/rng.h"
#include "stages/generate/foliage_placement.h"

namespace sylva::generate {

enum class Foliage { kLeaves, kNeedles };

// W&P's shape ratios 0-2 are kWeberPennShapeFloor + (1 - kWeberPennShapeFloor) f(r).
inline constexpr double kWeberPennShapeFloor = 0.2;

// Per-level parameters (Appendix A.2 branch-level + A.3 stem). Index 0 is the trunk; for the
// trunk Branches, DownAngleV, Rotate, RotateV and BranchRatio are unused. Angles in degrees as
// in the thesis (converted to radians inside).
struct LevelParams {
  double branches = 0;        // Branches: children per parent stem (W&P density rules)
  double length = 1;          // Length: trunk: fraction of Scale; level 1: of the trunk; deeper: of parent
  double length_v = 0;        // LengthV: ± variation of Length
  double taper = 1;           // Taper: 0 cylinder, 1 cone, 1–2 rounded tip, 2–3 periodic (W&P)
  double seg_splits = 0;      // SegSplits: clones per segment end (error-diffused)
  double split_angle_v = 0;   // SplitAngleV: ± variation of the natural split angle (deg)
  int curve_res = 3;          // CurveRes: segments per stem
  double curve = 0;           // Curve: bend over the stem (or its first half with CurveBack) (deg)
  double curve_v = 0;         // CurveV: ± random bend per stem, spread over segments (deg)
  double curve_back = 0;      // CurveBack: bend over the second half when non-zero (deg)
  double down_angle_v = 0;    // DownAngleV: variation of the natural down angle (deg); < 0: W&P's
                              // position-dependent form
  double rotate = 140;        // Rotate: azimuth step between successive children (deg); < 0 alternates
  double rotate_v = 0;        // RotateV: ± variation (deg)
  double branch_ratio = 0.5;  // BranchRatio S_s: child/primary radius ratio at attachments, (0, 1]
  // Clumps (ours, not W&P): children of this level gather into `clumps` equal groups along their
  // parent's child zone (less its bare `clump_base` fraction) instead of spreading evenly; each
  // group spans `clump_size` of its share of that, centred on it, so bare stretches of the parent
  // separate the groups. 0 = W&P's
  // even spread. Positions only: the draws per child are the same either way.
  int clumps = 0;           // Clumps: groups per parent, 0..100
  double clump_size = 0.3;  // ClumpSize: fraction of each group's share it spans, (0, 1]
  double clump_base = 0;    // ClumpBase: bare fraction of the zone before the groups, [0, 1)
};

// The leaf level (A.2): orientation of leaves/needles around and away from their branch.
struct LeafLevelParams {
  double down_angle_v = 0;    // deg
  double rotate = 137.5;      // deg
  double rotate_v = 0;        // deg
  double branch_ratio = 0.5;  // S_s that sets the natural leaf angle (Murray's y)
};

// Tree parameters (A.1, A.1.1, A.1.2).
struct Preset {
  int shape = 0;                      // Shape 0..7 (W&P shape ratio; 8 = envelope is not supported)
  int levels = 3;                     // Levels: branch levels, trunk included, 1..8
  double scale = 10, scale_v = 0;     // Scale, ScaleV: tree size (m)
  double base_size = 0.2;             // BaseSize: bare fraction of the trunk
  double ratio = 0.02;                // Ratio: trunk radius / trunk length
  double flare = 0.5;                 // Flare: trunk widening at the base
  int base_splits = 0;                // BaseSplits: clones after the first trunk segment
  double attraction_up = 0;           // AttractionUp: upward (< 0 downward) tendency, levels >= 2
  double tree_shape_exponent = 2.49;  // TreeShapeExponent E (da Vinci/Murray), > 1
  double leaves = 0;                  // Leaves: total leaves (or needles) on the last level
  double leaf_scale = 0.1;            // LeafScale: leaf (needle) length (m)
  double leaf_scale_x = 0.5;          // LeafScaleX: width / length (needle: diameter / length)
  double leaf_area_index = 0;         // LeafAreaIndex: target crown LAI; 0 = Leaves is the count
  double foliage_zone = 1;            // FoliageZone: distal fraction of a last-level branch in leaf
  double card_scale = 1;              // CardScale: multiplies card.length (an age's smaller shoots)
  // Hem (ours, not W&P; a weeping crown's lifted curtain): a branch of the last level that hangs
  // below Hem x the trunk's length ends there (its nodes are cut at that height, after its last
  // junction), each branch at its own Hem x (1 + HemV x u), u uniform in [-1, 1), one draw per
  // last-level branch after all growth draws and only when Hem > 0. 0 = none.
  double hem = 0;    // Hem: [0, 1)
  double hem_v = 0;  // HemV: [0, 1)
  // TrunkUp (ours, not W&P; an orthotropic leader): after the turns at each node of a level-0
  // branch (Curve, the primary deviations its laterals cause, a split), the branch turns back
  // towards the vertical by TrunkUp x its declination. 0 = none (Nystad: the primary deviations
  // add up along the trunk), 1 = the trunk stays vertical.
  double trunk_up = 0;  // TrunkUp: [0, 1]
  // ShapeFloor (ours): the level-1 length ratio at the crown's ends for Shapes 0-2, whose W&P
  // ratios are 0.2 + 0.8 f(r): with ShapeFloor F they are F + (1 - F) f(r) (a conifer's top
  // whorls are far shorter than a fifth of its longest branches). Other shapes: 0.2 only.
  double shape_floor = kWeberPennShapeFloor;  // ShapeFloor: [0, 1]
  // Pendulous (ours): with AttractionUp < 0, W&P's turn per segment, AttractionUp x declination /
  // CurveRes, vanishes for a branch pointing up, so a pendulous shoot that leaves upwards stands
  // up. Pendulous P measures the pull from the downward vertical instead:
  // AttractionUp x ((1 - P) declination + P (pi - declination)) / CurveRes (1: a shoot pointing
  // up flops over at once, one hanging straight down is left as it is). 0 = W&P.
  double pendulous = 0;  // Pendulous: [0, 1], 0 unless AttractionUp < 0
  Foliage foliage = Foliage::kLeaves;
  CardShape card;  // the preset's `card:` block (placement part)
  // Bark tint (Materials): the preset's textures.bark.lower_tint, heights as fractions of the
  // tree's height; from = to = 0 means none.
  tree::Color bark_tint{1, 1, 1};
  double bark_tint_from = 0, bark_tint_to = 0;
  std::vector<LevelParams> level;  // index = level; levels beyond the list reuse the last entry
  LeafLevelParams leaf;
  tree::Materials materials;  // copied into the tree as is
};

// Single leaves/needles (Nystad's one quad per leaf, and needles) or cards (twig cards for
// broadleaves, shoot cards for conifers).
enum class FoliageMode { kSingle, kCards };

// The leaf atlas the foliage refers to (the stage makes the texture; textures.h / card_atlas.h).
struct AtlasInfo {
  int columns = 2, rows = 2;
  std::vector<float> coverage;  // per cell, leaf-blade fraction; empty = 1
};

struct GenerateOptions {
  int levels = 0;                       // > 0 overrides Preset::levels
  double max_node_spacing = 0;          // m; > 0 inserts nodes so no segment is longer (§4.3.2)
  double leaf_density = 1;              // multiplies Leaves
  std::uint64_t max_nodes = 5'000'000;  // budget; exceeding it throws std::length_error
  std::string name;                     // copied to Tree::name
  FoliageMode foliage = FoliageMode::kSingle;
  AtlasInfo atlas;
  FoliageResult* foliage_result = nullptr;  // optional: how the foliage met its LAI target
};

// A parameter out of range. `key` is the parameter's path as the preset spells it
// ("Ratio", "levels[1].LengthV", "leaf.Rotate"), so the YAML reader can point at its line.
class PresetError : public std::invalid_argument {
 public:
  PresetError(std::string key, const std::string& message)
      : std::invalid_argument(message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// Checks every range (throws PresetError whose message reads "<key> must be ..."): the preset
// reader and the generator both call it, so the core never runs on nonsense.
void validate_preset(const Preset& preset);

// Generates the tree. Deterministic: the same (preset, options, rng state) gives the same tree
// bit for bit. Branch generation is breadth-first by level from the one Rng, so raising Levels
// from n to m leaves every branch of level <= n − 2 bit-identical, and the level n − 1 branches
// the same branches (index, level, parent; laterals also junction and first node): the natural
// rules make a branch react to its children (da Vinci radius steps, primary deviation), so the
// level that gains children cannot stay bit-identical. Foliage goes on the last level
// (foliage_placement.h), after the branches, from the same Rng. No branch goes below the ground:
// a non-root branch whose next node would come closer to y = 0 than ground_clearance(r) is
// turned up just enough (docs/stages/generate.md, "Ground").
// Throws std::invalid_argument (bad preset) or std::length_error (node budget exceeded).
tree::Tree generate_tree(const Preset& preset, const GenerateOptions& options, Rng& rng);

// The least height of a branch node of radius r above the ground (m): 1.5 r (the bark's square
// section before subdivision reaches 1.42 r) + 2 cm.
inline double ground_clearance(double r) { return 1.5 * r + 0.02; }

// W&P shape ratio f(shape, r) for r in [0, 1] (exposed for tests).
double shape_ratio(int shape, double r);

}  // namespace sylva::generate
