// Mip-safe alpha for an alpha-tested atlas: its coverage kept across the plain box-filtered
// mipmaps every glTF client builds (three.js, Babylon.js, Blender and sylva's renderer all call
// glGenerateMipmap or its like; a PNG in glTF cannot carry authored mipmaps).
//
// Seed: Castaño 2010, "Computing Alpha Mipmaps": alpha-tested foliage thins out with distance
// because a coarse texel averages leaf and gap and falls under the cutoff; Castaño rescales each
// level's alpha so the share of texels passing the test stays the base level's. A client's own
// mipmaps cannot be rescaled, so we put the reserve into the base level instead (our choice,
// docs/stages/generate.md "Mip-safe alpha"): around the leaves, alpha = gain × a blur of the
// leaf mask, always under the cutoff (invisible at full resolution), so a coarse texel over a
// cluster of leaves averages above the cutoff while one over open gaps does not. The gain is
// chosen, as Castaño chooses his scale, to keep each level's coverage (measured on the plain box
// mipmaps of libs/image) closest to the base level's; the blur radius is chosen with it.
#pragma once

#include <vector>

#include "stages/generate/textures.h"

namespace sylva::generate {

struct MipSafety {
  double gain = 0;                     // chosen halo gain (the halo is clamped under the cutoff)
  int radius = 0;                      // chosen blur radius (texels)
  std::vector<double> coverage;        // alpha-test coverage per mip level, [0] = base
  std::vector<double> coverage_plain;  // the same without the halo (for comparison)
};

// Adds the halo to `atlas` (columns x rows cells, blurred per cell so cells do not bleed) for
// alpha test at `cutoff` and returns what it measured on levels down to cells 2 texels across.
MipSafety make_mip_safe(Rgba8& atlas, int columns, int rows, float cutoff = 0.5f);

}  // namespace sylva::generate
