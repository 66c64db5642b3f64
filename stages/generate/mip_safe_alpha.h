// Mip-safe alpha for an alpha-tested atlas: its coverage kept across the plain box-filtered
// mipmaps every glTF client builds (three.js, Babylon.js, Blender and sylva's renderer all call
// glGenerateMipmap or its like; a PNG in glTF cannot carry authored mipmaps).
//
// Seed: Castaño 2010, "Computing Alpha Mipmaps": alpha-tested foliage thins out with distance
// because a coarse texel averages leaf and gap and falls under the cutoff; Castaño rescales each
// level's alpha so the share of texels passing the test stays the base level's. A client's own
// mipmaps cannot be rescaled, so we put the reserve into the base level instead (our choice,
// docs/stages/generate.md "Mip-safe alpha"): around the leaves, alpha = gain x a blur of the
// leaf mask, always under the cutoff (invisible at full resolution), so a coarse texel over a
// cluster of leaves averages above the cutoff while one over open gaps does not. The gain and the
// blur radius are chosen, as Castaño chooses his scale, so that the coverage the alpha test keeps
// when a client DRAWS the atlas (image::sampled_alpha_coverage: trilinear samples of the box
// mipmaps, which average a coarse level once more than its stored texels show) stays closest
// (least mean factor) to the base level's at the levels of detail down to cells one texel across.
// At the coarsest of those levels a cell is one or two texels: a card there is drawn whole or not
// at all, and drawn whole (a denser crown) is the lesser error than vanishing (a bare tree).
#pragma once

#include <vector>

#include "stages/generate/textures.h"

namespace sylva::generate {

struct MipSafety {
  double gain = 0;                     // chosen halo gain (the halo is clamped under the cutoff)
  double cap = 0;                      // chosen halo ceiling (<= the cutoff less 1/255)
  int radius = 0;                      // chosen blur radius (texels)
  std::vector<double> lods;            // levels of detail measured: 0, 0.5, ... (see make_mip_safe)
  std::vector<double> coverage;        // alpha-test coverage drawn at each of `lods`, [0] = base
  std::vector<double> coverage_plain;  // the same without the halo (for comparison)
};

// Adds the halo to `atlas` (columns x rows cells, blurred per cell so cells do not bleed) for
// alpha test at `cutoff` and returns what it measured at levels of detail 0, 0.5, ... up to
// log2(the cell's short side) + 0.5. Only alpha under the cutoff changes.
MipSafety make_mip_safe(Rgba8& atlas, int columns, int rows, float cutoff = 0.5f);

}  // namespace sylva::generate
