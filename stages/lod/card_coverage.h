// What cards draw: each atlas variant's opaque fraction, and the drawn coverage of a set of cards
// seen from a level's switch distance, so a card-cluster cut can be held to the coverage of the
// cut it replaces (`card_coverage_check`, docs/stages/lod.md "Card clusters").
//
// Definitions (ours):
//   * alpha_v, the opacity of atlas variant v: the fraction of the texels of v's cell
//     (tree::atlas_cell) whose alpha is >= the MASK cutoff, i.e. what a renderer draws of a
//     card at full resolution (blades, needles, and the twig or stem too). Without an atlas the
//     tree's own cell_coverage (tree.h) stands in, and 1 without that.
//   * The drawn coverage of cards C from a horizontal direction v at pixel size s: the cards'
//     corners projected on the plane orthogonal to v, a raster of s x s pixels over the box of
//     both card sets compared, each card splatted as n x n bilinear samples (n = ceil(2 e / s),
//     e its longest projected edge, 1..16), each sample depositing alpha_c P_c / n^2 (P_c its
//     projected area) into its pixel's density D; a pixel draws 1 - exp(-D / s^2) of itself
//     (independent overlap of sub-pixel cards) and the view draws the sum of that times s^2.
//     Four directions: azimuths 0, 45, 90 and 135 degrees (the opposite ones draw the same).
//   * The drift of cut A against cut B: of the four directions' relative differences
//     (coverage_A - coverage_B) / coverage_B (0 when B draws nothing and A neither, else 1), the
//     one of largest magnitude, with its sign (negative: A draws less).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "libs/tree/tree.h"
#include "stages/lod/foliage.h"

namespace sylva::lod {

// alpha_v of every cell of the atlas (atlas_columns x atlas_rows values, variant order) from
// `rgba` (width x height texels, 4 bytes each, rows top to bottom), alpha >= cutoff (0..1) counted
// as drawn. Throws std::invalid_argument when the sizes disagree or the image is empty.
std::vector<double> measure_cell_opacity(std::span<const std::uint8_t> rgba, int width, int height,
                                         const tree::Materials& materials, double cutoff = 0.5);

// The alpha of the cell a quad shows (the cell holding the mean of its uvs: an original card, an
// FSA-collapsed leaf and a cluster survivor each show one whole cell): `per_variant[v]` when
// given (one value per cell), else tree::cell_coverage.
double card_opacity(const LeafQuad& quad, const tree::Materials& materials,
                    std::span<const double> per_variant);

// The drift of cards `a` (opacities `alpha_a`, one per card) against cards `b` at pixel size
// `pixel_m` (> 0; the raster is coarsened to at most 1024 pixels a side). File comment.
double coverage_drift(std::span<const LeafQuad> a, std::span<const double> alpha_a,
                      std::span<const LeafQuad> b, std::span<const double> alpha_b, double pixel_m);

// The drawn coverage (m^2) of cards `cards` from each of the four directions, on the raster of
// pixel size `pixel_m` over their own box (the quantity coverage_drift compares).
std::vector<double> drawn_coverage(std::span<const LeafQuad> cards, std::span<const double> alpha,
                                   double pixel_m);

}  // namespace sylva::lod
