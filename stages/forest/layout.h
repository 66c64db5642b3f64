// Forest layout: where every tree stands (pure: plain data in, plain data out; no I/O).
//
// Seed: Celba, "Dynamic Level of Detail" (2007), §4.5.2–4.5.3 and Algorithm 8 (PlaceTreesIntoForest, run by
// CreateForest): per tree type a density (trees per 10 000 m²) over a Width x Depth area, per-axis scale
// ranges (SizeDeviationX/Y/Z Min/Max), a base rotation about X, Y, Z and translation along Y; the types are
// placed in order (type 0 first), each tree at a uniform random position with a random scale; its box (the
// type's base-transformed box, scaled) is tested against the boxes already placed, found through an index
// (Celba: a quadtree; here a uniform grid, box_grid.h), and the tree is rejected when the overlap volume with
// ANY ONE placed box exceeds AllowIntersection times its own volume; a rejected tree is drawn again up to
// NumberOfRetries times, then dropped (the forest may hold fewer trees than requested).
//
// Beyond Celba (his §4.5.4 "possible improvements", and what scatter tools offer), each optional:
// an explicit seed (same inputs -> same forest; his §5.3: "it isn't easy to generate same tree
// positions"); a random yaw (the box tested is then the
// axis-aligned box of the yawed box); terrain (trees stand on the height field; per-species slope
// and altitude limits); a density map multiplying every density; exclusion polygons; rows and
// alleys (polylines with spacing and jitter); explicit positions (positions_csv.h); and `poisson`, a
// Bridson-style variable-radius Poisson-disk sampler with a minimum spacing per species, in place of Celba's
// method. docs/stages/forest.md maps every parameter to its source.
//
// Placement order (and so the ids): explicit positions, then rows, then the random fill (types in
// order). Explicit and row trees are not overlap-tested (they are the user's intent) but enter
// the index, so the random fill keeps clear of them; they do obey the exclusion polygons and
// the species' slope and altitude limits (a tree that breaks one is reported as dropped).
//
// Conventions: metres, Y up; the area is [-width/2, width/2] x [-depth/2, depth/2]; a tree's
// position is its base point (on the ground); yaw is about +Y.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "libs/forest/instances.h"
#include "pipeline/rng.h"
#include "stages/forest/fields.h"

namespace sylva::forest {

enum class Method { kCelba, kPoisson };

using Point2 = std::array<double, 2>;  // (x, z)

struct SpeciesRule {
  std::string name;
  Box3 bounds;                                             // the asset's object-space box
  double density_per_ha = 0;                               // trees per 10 000 m² (Celba's Density)
  Point2 scale_x{1, 1}, scale_y{1, 1}, scale_z{1, 1};      // [min, max] per axis (SizeDeviation*)
  Vec3d base_rotation_deg{0, 0, 0};                        // BaseRotationX/Y/Z
  double base_translation_y_m = 0;                         // BaseTranslationY
  bool random_yaw = true;                                  // yaw uniform in [0, 2 pi)
  double max_slope_deg = 90;                               // terrain: no tree where the ground is steeper
  double min_altitude_m = -1e300, max_altitude_m = 1e300;  // terrain: allowed heights of the ground
  double min_spacing_m =
      0;  // poisson: no other tree closer than this (0: the box's half diagonal on the ground)
};

struct Row {
  std::uint32_t species = 0;
  std::vector<Point2> points;  // polyline, >= 2 points
  double spacing_m = 5;        // along the polyline, the first tree at its start
  double jitter_m = 0;         // each tree moved uniformly within this radius
};

struct ExplicitTree {
  std::uint32_t species = 0;
  Point2 position{0, 0};
  double yaw_deg = -1;  // < 0: random (when the species has random_yaw), else 0
  double scale = -1;    // < 0: random in the species' ranges; > 0: uniform scale
  int line = 0;         // source line (for messages)
};

struct LayoutParams {
  double width_m = 100, depth_m = 100;  // Celba's Width, Depth
  Method method = Method::kCelba;
  double allow_intersection = 0;  // Celba's AllowIntersection, [0, 1]
  int retries = 10;               // Celba's NumberOfRetries (poisson: candidates per active point)
  std::vector<SpeciesRule> species;
  Terrain terrain;                              // empty: flat ground at y = 0
  Field density;                                // empty: 1 everywhere
  std::vector<std::vector<Point2>> exclusions;  // polygons (x, z), even-odd rule
  std::vector<Row> rows;
  std::vector<ExplicitTree> explicit_trees;
};

struct PlacedTree {
  std::uint32_t species = 0;
  Vec3d position{0, 0, 0};
  double yaw_rad = 0;
  Vec3d scale{1, 1, 1};
  Box3 box;  // world box used by the overlap test (and the hierarchy)
};

struct LayoutResult {
  std::vector<PlacedTree> trees;    // in placement order (= id order)
  std::vector<SpeciesStats> stats;  // per species
};

// B_species (Celba's base transform) of a rule, and the tree's world box: the axis-aligned box of
// R_y(yaw) S B applied to `bounds`, translated to the position.
Box3 tree_box(const SpeciesRule& s, const Vec3d& position, double yaw_rad, const Vec3d& scale);

// Fraction in [0, 1] of the area where species s may grow (density map x not excluded x terrain
// limits), estimated on a 256 x 256 grid of cell centres: Celba's expected count is
// density x width x depth / 10^4 times this.
double allowed_fraction(const LayoutParams& p, std::uint32_t species);

// Trees the parameters request before any is placed or dropped: explicit positions, one per
// row spacing along every row segment (plus its start), and each species' expected count
// (density x area x allowed_fraction, rounded).
double requested_trees(const LayoutParams& p);

// Lays out the forest. `rng` is the stage's stream (every random draw comes from it, in a fixed
// order, so the result is a function of the parameters and the seed). `cancelled` is called
// now and then and may throw. Throws std::invalid_argument for impossible parameters (message
// says which), among them more than 20,000,000 requested trees (requested_trees).
LayoutResult lay_out(const LayoutParams& p, Rng& rng, const std::function<void()>& cancelled = {});

// Point in polygon, even-odd rule.
bool inside_polygon(const std::vector<Point2>& polygon, const Point2& p);

}  // namespace sylva::forest
