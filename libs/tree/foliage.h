// Foliage helpers every stage shares: the one definition of the leaf atlas layout (a leaf's
// variant -> its texture rectangle), one-sided leaf area, the crown's projected area and leaf
// area index, and which twigs their cards draw.
//
// Seeds: Nystad 2010 §5.5.4 (a leaf quad shows one cell of a leaf texture chosen by its "type");
// Bréda 2003, "Ground-based measurements of leaf area index" (J. Exp. Bot. 54:2403): LAI is the
// total one-sided leaf area per unit ground surface area. For one tree we divide by the crown's
// projected area (its vertical projection, the forester's "crown projection area"), which we
// take as the convex hull of the foliage seen from above (our choice; docs/tree-format.md).
#pragma once

#include <cstddef>
#include <vector>

#include "libs/tree/tree.h"

namespace sylva::tree {

// A texture rectangle in glTF uv (origin at the image's top-left): u0 < u1 across, v0 < v1 down.
// A leaf quad maps v0 to its base (petiole, twig base) and v1 to its tip, u0 to the -side edge
// (side = cross(normal, direction)) and u1 to the +side edge.
struct UvRect {
  float u0 = 0, v0 = 0, u1 = 1, v1 = 1;
  friend bool operator==(const UvRect&, const UvRect&) = default;
};

// The atlas cell of `variant`: column variant % atlas_columns, row variant / atlas_columns, each
// cell 1/columns wide and 1/rows tall. Variants beyond the atlas wrap (validate_tree refuses them
// in a tree; this keeps the function total).
UvRect atlas_cell(const Materials& materials, unsigned variant);

// The fraction of `variant`'s cell covered by leaf blades (1 when the materials give none).
double cell_coverage(const Materials& materials, unsigned variant);

// One-sided leaf area of one leaf quad (m^2): length * width * its cell's coverage.
double leaf_area(const Materials& materials, const Leaf& leaf);

// Projected (silhouette) area of a needle seen side-on, 2 r l (m^2): the one-sided area forestry
// uses for needles ("projected LAI").
double needle_area(const Needle& needle);

// Area (m^2) of the convex hull of points given as (x, z) pairs; 0 for fewer than 3 distinct
// points. Andrew's monotone chain, O(n log n); hand-written so libs/tree keeps no dependencies.
double convex_hull_area(std::vector<std::pair<double, double>> points);

struct CrownFoliage {
  double leaf_area = 0;   // m^2, one-sided: leaves (coverage-weighted quads) + needle silhouettes
  double crown_area = 0;  // m^2, convex hull of every foliage corner/end point projected on y = 0
  double lai() const { return crown_area > 0 ? leaf_area / crown_area : 0.0; }
};

// Leaf area, crown projected area and their ratio (the crown's leaf area index).
CrownFoliage crown_foliage(const Tree& tree);

// Per branch: 1 if its cards draw it — leaf_kind is a card kind, no branch grows from it, and one
// of its cards starts within that card's length of the branch's first node (the cards reach its
// base; a twig in leaf only at its tip keeps its bark) — else 0. Empty for LeafKind::kLeaves.
std::vector<char> twigs_drawn_by_cards(const Tree& tree);

}  // namespace sylva::tree
