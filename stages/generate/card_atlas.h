// The procedural card atlas: per species, eight variants (4 columns x 2 rows) of a twig with
// its leaves, petioles and stem (broadleaves), or of a conifer shoot with its needles. Pure:
// pixels in, no I/O; every random choice from the Rng passed in.
//
// Seeds: Nystad 2010 §5.5.4 (a leaf quad shows one cell of a leaf texture, its "type"); the
// cards themselves follow the games practice (ez-tree, SpeedTree: one alpha-masked quad carrying
// a twig). Our own construction (docs/stages/generate.md, "Card atlas"):
//   - A cell is the card seen from its front: x across (the card's width, aspect x length),
//     y from the card's base (the image row at the cell's top, low v) to its tip. The stem
//     enters at the middle of the top edge, so a card placed on a twig continues it.
//   - twig: a gently bent stem with `shoots` side shoots (alternating, 30–50°), `elements`
//     leaves (± 1) shared by the axes by length, alternating left and right, each on a petiole,
//     at the preset's leaf angle ± 15°, foreshortened (width x 0.75..1) as leaves seen at an
//     angle, spread along the axis or gathered at its tip (`cluster`), a terminal leaf per axis;
//     leaf blades use the species' silhouette (textures.h) at the preset's leaf size.
//   - tuft (pines): a branchlet, a stem with `shoots` side shoots, each axis a bristly bottle
//     brush of needles on its distal 38 % (denser towards the tip) at the preset's angle ± 15°
//     all round the axis, ending in a starburst of needles up to 80° around its tip; `elements`
//     needles shared by the axes by length.
//   - spray (spruces): a main axis with `shoots` (+ 0..1) side shoots, shorter towards the tip,
//     needles all round every axis at the preset's angle ± 12° (a comb seen from the side).
//   - Needles of a brush are drawn as their projection onto the card (a needle at cone angle
//     theta and azimuth phi around its axis points atan2(sin theta cos phi, cos theta) from it,
//     shortened accordingly), at least one texel wide; their projected area counts.
//   - Colours: blades from the leaf colour with a per-leaf tint, midrib and lateral veins in the
//     vein colour, one half of the blade lighter (a folded leaf); stems from the bark colours.
//     Fully transparent texels take the cell's mean leaf colour, so filtering never bleeds a
//     dark fringe into the silhouette.
//   - Coverage: per cell, the leaf (or needle) area drawn — the sum of the blades' areas
//     integrated from their outlines, overlaps counted (each is real leaf area), stems and
//     petioles excluded — divided by the cell's area. It is resolution independent, so the
//     tree's leaf area index does not depend on texture_size.
#pragma once

#include <vector>

#include "pipeline/rng.h"
#include "stages/generate/textures.h"

namespace sylva::generate {

enum class CardStyle { kTwig, kTuft, kSpray };

struct CardLook {
  CardStyle style = CardStyle::kTwig;
  int elements = 8;            // leaves per twig (twig) or needles per shoot (tuft, spray)
  int shoots = 2;              // side shoots off the card's main stem (twig, spray)
  double petiole = 0.15;       // petiole length / leaf length (twig)
  double leaf_angle_deg = 50;  // leaves or needles from the stem (deg)
  double cluster = 0;          // 0: spread along the stem, 1: gathered at its tip
  double length_m = 0.4;       // card length (m)
  double aspect = 0.8;         // card width / length
  double leaf_length_m = 0.1;  // leaf (needle) length (m): the preset's LeafScale
  double leaf_width = 0.5;     // leaf width / length (needle diameter / length): LeafScaleX
};

inline constexpr int kCardAtlasColumns = 4;
inline constexpr int kCardAtlasRows = 2;

struct CardAtlas {
  Rgba8 image;  // size x size, straight alpha
  int columns = kCardAtlasColumns, rows = kCardAtlasRows;
  std::vector<float> coverage;  // per cell (variant order), leaf area / cell area, in [0, 1]
};

// Throws std::invalid_argument for a size that is not a power of two in [16, 8192].
CardAtlas make_card_atlas(const CardLook& card, const LeafLook& leaf, const BarkLook& bark, int size,
                          Rng& rng);

}  // namespace sylva::generate
