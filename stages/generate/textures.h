// Deterministic procedural textures per species: a tileable bark texture and a 2x2 RGBA leaf
// atlas (four variants with an alpha silhouette, petiole at low v, i.e. near the top edge of
// each quadrant in image rows; layout in docs/tree-format.md). Pure: pixels in, no I/O.
//
// Seeds: Nystad 2010 §5.5.4 (leaf "type" selects one of four texture quadrants); Celba 2007
// (leaf textures with the petiole at low v). The patterns themselves are our own: periodic value
// noise (so the bark tiles exactly in u and v) shaped per bark style, and leaf silhouettes from
// a polar/profile function per leaf shape. Every random choice comes from the Rng passed in.
#pragma once

#include <cstdint>
#include <vector>

#include "libs/tree/tree.h"
#include "pipeline/rng.h"

namespace sylva::generate {

enum class BarkStyle { kFissured, kSmooth, kBirch, kScaly };
enum class LeafShape { kLobed, kOvate, kPalmate, kSpiny, kLanceolate, kNeedle };

// Colours are sRGB in [0, 1] (as an artist picks them).
struct BarkLook {
  BarkStyle style = BarkStyle::kFissured;
  tree::Color color{0.40f, 0.33f, 0.26f};  // ridges / main surface
  tree::Color dark{0.16f, 0.12f, 0.09f};   // fissures, lenticels, plate edges
};

struct LeafLook {
  LeafShape shape = LeafShape::kOvate;
  tree::Color color{0.22f, 0.40f, 0.12f};  // blade
  tree::Color vein{0.45f, 0.55f, 0.25f};   // midrib, veins and petiole
};

// 8-bit RGBA, rows top to bottom, 4 bytes per pixel.
struct Rgba8 {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
};

// size x size, tileable: the pixel after the last column/row is the first one again.
Rgba8 make_bark_texture(const BarkLook& look, int size, Rng& rng);

// size x size atlas, four leaf variants in 2x2 quadrants; alpha is 0 outside the silhouettes.
// `coverage` (optional) receives each quadrant's blade area fraction (petiole excluded),
// integrated from the outline independently of `size`.
Rgba8 make_leaf_atlas(const LeafLook& look, int size, Rng& rng, std::vector<float>* coverage = nullptr);

// Per-variant variation of a leaf silhouette.
struct LeafVariant {
  double width = 0.9;  // overall half-width scale
  double phase = 0;    // lobe phase
  double bend = 0;     // midrib bend (fraction of the half-width at the tip)
  double tint = 1;     // brightness factor
  double lobes = 4.5;  // lobes per side (lobed / spiny)
};

// Half-width of a blade of `shape` at tau in [0, 1] from its base to its tip, as a fraction of
// the leaf's half-width (0 outside (0, 1)).
double blade_half_width(LeafShape shape, double tau, const LeafVariant& v);

// sRGB [0, 1] -> linear (for Materials base colours).
tree::Color srgb_to_linear(tree::Color c);

}  // namespace sylva::generate
